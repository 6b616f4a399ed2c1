// The loadable module with OpenCV's image files and FastLineDetector (opencv_extra_abi.h says why
// they are a module). Each entry is the OpenCV call itself, so pixels and file bytes are unchanged.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/ximgproc.hpp>

#include "plugins/opencv_extra_abi.h"

namespace {

cv::Mat Imread(const std::string& path, int flags) { return cv::imread(path, flags); }

bool Imwrite(const std::string& path, const cv::Mat& image, const std::vector<int>& params) {
  return cv::imwrite(path, image, params);
}

bool Imencode(const std::string& ext, const cv::Mat& image, std::vector<uchar>& out,
              const std::vector<int>& params) {
  return cv::imencode(ext, image, out, params);
}

void FastLines(const cv::Mat& grey, int length_threshold, float distance_threshold, double canny_low,
               double canny_high, int canny_aperture, bool merge, std::vector<cv::Vec4f>& lines) {
  const cv::Ptr<cv::ximgproc::FastLineDetector> fld = cv::ximgproc::createFastLineDetector(
      length_threshold, distance_threshold, canny_low, canny_high, canny_aperture, merge);
  fld->detect(grey, lines);
}

const dynref::plugins::OpenCvExtra kTable{dynref::plugins::kOpenCvExtraAbi, &Imread, &Imwrite,
                                          &Imencode, &FastLines};

}  // namespace

extern "C" __attribute__((visibility("default"))) const dynref::plugins::OpenCvExtra*
dynref_opencv_extra() {
  return &kTable;
}
