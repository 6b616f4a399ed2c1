#include "detect/onnx_model.h"

#include <algorithm>
#include <cctype>
#include <fstream>

#include "core/error.h"
#include "core/sha256.h"

namespace dynref::detect {

LoadedModel LoadOnnxModel(const std::string& path, const std::string& expected_sha256,
                          const std::string& what) {
  if (path.empty()) throw InputError("<model>", what + ": no model path given");
  if (!std::ifstream(path, std::ios::binary))
    throw InputError(path, what + " model not found or unreadable");
  LoadedModel m;
  m.path = path;
  m.sha256 = Sha256File(path);
  std::string expected = expected_sha256;
  std::transform(expected.begin(), expected.end(), expected.begin(),
                 [](unsigned char ch) { return char(std::tolower(ch)); });
  if (!expected.empty() && expected != m.sha256)
    throw InputError(path, what + " model sha256 mismatch: expected " + expected + ", file has " + m.sha256 +
                               " (wrong or corrupted file; see models/README.md)");
  try {
    m.net = cv::dnn::readNetFromONNX(path);
  } catch (const cv::Exception& e) {
    throw InputError(path, what + " model is not a loadable ONNX network: " + e.msg);
  }
  if (m.net.empty()) throw InputError(path, what + " model is not a loadable ONNX network");
  m.net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  m.net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  return m;
}

}  // namespace dynref::detect
