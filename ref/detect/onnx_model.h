// Loading an ONNX network into OpenCV DNN (CPU, default backend) after checking the file's
// sha256, so a run can record exactly which weights produced its detections.
#pragma once
#include <opencv2/dnn.hpp>
#include <string>

namespace dynref::detect {

struct LoadedModel {
  cv::dnn::Net net;
  std::string path;
  std::string sha256;
};

// InputError (naming the file) when the file is missing/unreadable, its sha256 differs from
// expected_sha256 (when non-empty), or OpenCV cannot parse it.
LoadedModel LoadOnnxModel(const std::string& path, const std::string& expected_sha256,
                          const std::string& what);

}  // namespace dynref::detect
