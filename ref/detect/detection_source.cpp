#include "detect/detection_source.h"

#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "core/resources.h"
#include "detect/sources.h"
#include "io/coco_classes.h"

namespace dynref {

const char* const kNanodetSha256 = "70fda317330d4a961db7c4408e199022f0e9361a183e46b4cd302eba612988c0";
const char* const kSelfieSha256 = "f008c9552c340278ecccd5954e1007ba2846c080fda59dc5b70e0876b774531d";

std::string BundledModelPath(const std::string& file_name) {
  // DYNREF_MODELS_DIR (environment) overrides the data folder's models/ (core/resources.h:
  // <exe>/../share/dynref when installed, else the source tree); the file contents are still
  // checked against the bundled sha256.
  const char* env = std::getenv("DYNREF_MODELS_DIR");
  const std::string dir = (env && *env) ? std::string(env) : ResourcePath("models");
  return dir + "/" + file_name;
}

void DetectSourceOptions::Check() const {
  const std::string where = "<detect options>";
  if (std::isnan(confidence_threshold) || confidence_threshold > 1)
    throw InputError(where, "confidence_threshold must be <= 1 (or < 0 for the default)");
  if (!(nms_iou > 0 && nms_iou <= 1)) throw InputError(where, "nms_iou must be in (0, 1]");
  if (max_detections < 1 || max_detections > 65535) throw InputError(where, "max_detections must be in 1..65535");
  if (yolo_input_size < 32 || yolo_input_size % 32 != 0)
    throw InputError(where, "yolo_input_size must be a positive multiple of 32");
}

namespace {
const char* const kKnownSpecs =
    "files:DIR, labels:DIR, gt, gt:MODE, nanodet, hog, onnx-yolo[:MODEL], onnx-maskrcnn[:MODEL], onnx-yolact[:MODEL]";
}  // namespace

void CheckDetectionSpec(const std::string& spec, const DetectSourceOptions& options, const std::string& option) {
  const size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : spec.substr(colon + 1);
  const auto need_arg = [&](const std::string& what) {
    if (arg.empty()) throw InputError(option, "source '" + kind + "' needs " + what + " ('" + kind + ":...')");
  };
  const auto no_arg = [&] {
    if (colon != std::string::npos) throw InputError(option, "source '" + kind + "' takes no ':' argument");
  };
  if (kind == "files") return need_arg("a dynref-detections folder");
  if (kind == "labels") return need_arg("a label-PNG folder with labels.yaml");
  if (kind == "gt") {
    if (options.sequence_root.empty())
      throw InputError(option, "source '" + spec + "' reads a synthetic sequence: give the sequence folder");
    return;
  }
  if (kind == "nanodet" || kind == "hog") return no_arg();
  if (kind == "onnx-yolo" || kind == "onnx-maskrcnn" || kind == "onnx-yolact") {
    if (arg.empty() && options.model_path.empty())
      throw InputError(option, "source '" + kind + "' needs a model: '" + kind + ":PATH' or --model PATH");
    return;
  }
  throw InputError(option, "unknown detection source '" + spec + "' (known: " + kKnownSpecs + ")");
}

std::unique_ptr<DetectionSource> MakeDetectionSource(const std::string& spec,
                                                     const DetectSourceOptions& options) {
  options.Check();
  CheckDetectionSpec(spec, options);
  const size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (kind == "files") return detect::MakeFolderSource(arg);
  if (kind == "labels") return detect::MakeLabelPngSource(arg);
  if (kind == "gt")
    return detect::MakeFolderSource(arg.empty() ? options.sequence_root + "/gt"
                                                : options.sequence_root + "/detections/" + arg);
  if (kind == "nanodet") return detect::MakeNanodetSource(options);
  if (kind == "hog") return detect::MakeHogSource(options);
  const std::string model = arg.empty() ? options.model_path : arg;
  if (kind == "onnx-maskrcnn" || kind == "onnx-yolact") return detect::MakeOnnxInstanceSource(kind, model, options);
  return detect::MakeOnnxYoloSource(model, options);  // onnx-yolo
}

namespace detect {

void RequireBgrImage(const cv::Mat& bgr, const std::string& stamp_text, const std::string& source) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw InputError("frame " + stamp_text, source + " needs a non-empty 8-bit BGR image");
}

std::vector<std::string> CocoClassNames() {
  std::vector<std::string> names;
  for (int i = 0; i < kCocoClassCount; ++i) names.push_back(CocoClassName(i));
  return names;
}

void PaintInstanceMasks(const std::vector<Candidate>& kept, cv::Size image,
                        const std::function<cv::Mat(const Candidate&)>& mask_of, FrameDetections& frame) {
  cv::Mat ids = cv::Mat::zeros(image, CV_16U);
  for (size_t i = kept.size(); i-- > 0;) ids.setTo(frame.instances[i].id, mask_of(kept[i]));
  bool any = false;
  for (DetectedInstance& d : frame.instances) {
    d.has_mask = cv::countNonZero(ids == d.id) > 0;
    any = any || d.has_mask;
  }
  if (any) frame.instance_ids = ids;
}

FrameDetections CandidatesToFrame(const std::vector<Candidate>& kept, const std::string& stamp_text,
                                  const std::vector<std::string>& class_names) {
  FrameDetections frame;
  frame.stamp_text = stamp_text;
  int id = 1;
  for (const Candidate& c : kept) {
    DetectedInstance d = ToCocoInstance(c, id++);
    const bool named = c.class_id >= 0 && c.class_id < int(class_names.size());
    d.class_name = named ? class_names[c.class_id] : "class_" + std::to_string(c.class_id);
    d.class_id = CocoClassId(d.class_name);
    frame.instances.push_back(d);
  }
  return frame;
}

}  // namespace detect
}  // namespace dynref
