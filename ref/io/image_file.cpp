#include "io/image_file.h"

#include "plugins/opencv_extra_abi.h"

namespace dynref {

cv::Mat ImageRead(const std::string& path, int flags) {
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
