#include "io/image_file.h"

#include <algorithm>
#include <cctype>

#include "io/png_decode.h"
#include "plugins/opencv_extra_abi.h"

namespace dynref {
namespace {

bool EndsWithPng(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png";
}

}  // namespace

// A sequence's own PNGs (8-bit RGB, 16-bit depth) decode on libdeflate (io/png_decode.h), with the
// very pixels OpenCV gives; every other image and flag goes to OpenCV.
cv::Mat ImageRead(const std::string& path, int flags) {
  cv::Mat fast;
  if (flags == cv::IMREAD_UNCHANGED && EndsWithPng(path) && ReadPngFast(path, &fast)) return fast;
  return plugins::OpenCvExtraModule().imread(path, flags);
}

bool ImageWrite(const std::string& path, const cv::Mat& image, const std::vector<int>& params) {
  return plugins::OpenCvExtraModule().imwrite(path, image, params);
}

bool ImageEncode(const std::string& ext, const cv::Mat& image, std::vector<uchar>& out,
                 const std::vector<int>& params) {
  return plugins::OpenCvExtraModule().imencode(ext, image, out, params);
}

}  // namespace dynref
