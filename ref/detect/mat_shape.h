// The shape of an n-dimensional cv::Mat as "[d0, d1, ...]", for messages about ONNX outputs.
#pragma once
#include <opencv2/core.hpp>
#include <string>

namespace dynref::detect {

inline std::string MatShapeText(const cv::Mat& m) {
  std::string s = "[";
  for (int i = 0; i < m.dims; ++i) s += (i ? ", " : "") + std::to_string(m.size[i]);
  return s + "]";
}

}  // namespace dynref::detect
