// Image files: cv::imread / cv::imwrite / cv::imencode run in the OpenCV module
// (plugins/opencv_extra_abi.h), loaded at the first call, so that processes that never touch an
// image do not load imgcodecs and GDAL (core/modules.h). Same arguments and results as OpenCV's.
#pragma once
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>  // the cv::IMREAD_* / cv::IMWRITE_* flags (no imgcodecs symbol is linked)
#include <string>
#include <vector>

namespace dynref {

cv::Mat ImageRead(const std::string& path, int flags = cv::IMREAD_COLOR);
bool ImageWrite(const std::string& path, const cv::Mat& image, const std::vector<int>& params = {});
bool ImageEncode(const std::string& ext, const cv::Mat& image, std::vector<uchar>& out,
                 const std::vector<int>& params = {});

}  // namespace dynref
