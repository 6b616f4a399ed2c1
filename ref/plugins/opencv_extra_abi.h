// The interface between dynref and the OpenCV module (opencv_extra.cpp, built as the loadable
// dynref_opencv_extra.so): image files (imgcodecs) and the FastLineDetector (ximgproc). These two
// OpenCV libraries pull in GDAL and ~140 shared libraries that cost ~0.2 CPU-s at every process
// start; as a module only the processes that read or write an image pay it (core/modules.h).
// Image files go through io/image_file.h.
#pragma once
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/modules.h"

namespace dynref::plugins {

// The module's function table. C++ types cross the boundary: the module is built by the same
// build with the same compiler and links the same libopencv_core.
struct OpenCvExtra {
  int abi_version;
  cv::Mat (*imread)(const std::string& path, int flags);
  bool (*imwrite)(const std::string& path, const cv::Mat& image, const std::vector<int>& params);
  bool (*imencode)(const std::string& ext, const cv::Mat& image, std::vector<uchar>& out,
                   const std::vector<int>& params);
  // cv::ximgproc::createFastLineDetector(length, distance, canny_low, canny_high, aperture,
  // merge)->detect(grey, lines).
  void (*fast_lines)(const cv::Mat& grey, int length_threshold, float distance_threshold,
                     double canny_low, double canny_high, int canny_aperture, bool merge,
                     std::vector<cv::Vec4f>& lines);
};

constexpr int kOpenCvExtraAbi = 1;

#define DYNREF_OPENCV_EXTRA_MODULE "dynref_opencv_extra.so"
#define DYNREF_OPENCV_EXTRA_SYMBOL "dynref_opencv_extra"  // extern "C" const OpenCvExtra* ()

// The module's table, loaded at the first call (core/modules.h); throws std::runtime_error when
// the module is missing or was built for another version of this table.
inline const OpenCvExtra& OpenCvExtraModule() {
  using Entry = const OpenCvExtra* (*)();
  static const OpenCvExtra* table = [] {
    const auto entry =
        reinterpret_cast<Entry>(ModuleSymbol(DYNREF_OPENCV_EXTRA_MODULE, DYNREF_OPENCV_EXTRA_SYMBOL));
    const OpenCvExtra* t = entry();
    if (t->abi_version != kOpenCvExtraAbi)
      throw std::runtime_error(std::string(DYNREF_OPENCV_EXTRA_MODULE) + " has table version " +
                               std::to_string(t->abi_version) + ", this build expects " +
                               std::to_string(kOpenCvExtraAbi));
    return t;
  }();
  return *table;
}

}  // namespace dynref::plugins
