// `onnx-yolo` source: a user's YOLOv8 / YOLO11 detect or seg model exported to ONNX at opset
// <= 12 (OpenCV 4.6 mis-reads newer Split nodes); raw head outputs decoded in yolo_decode.cpp.
#include <opencv2/dnn.hpp>
#include <algorithm>
#include <fstream>

#include "core/error.h"
#include "detect/onnx_model.h"
#include "detect/sources.h"
#include "detect/yolo_decode.h"

namespace dynref::detect {
namespace {

constexpr double kYoloDefaultThreshold = 0.25;  // Ultralytics predict default conf

std::vector<std::string> ReadClassNames(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open class names file");
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::replace(line.begin(), line.end(), ' ', '_');  // one token in the mask format
    names.push_back(line);
  }
  if (names.empty()) throw InputError(path, "class names file is empty");
  return names;
}

class OnnxYoloSource : public DetectionSource {
 public:
  OnnxYoloSource(const std::string& model_path, const DetectSourceOptions& options) : options_(options) {
    model_ = LoadOnnxModel(model_path, options.model_sha256, "YOLO");
    threshold_ = options.confidence_threshold >= 0 ? options.confidence_threshold : kYoloDefaultThreshold;
    if (!options.class_names_file.empty()) class_names_ = ReadClassNames(options.class_names_file);
    output_names_ = model_.net.getUnconnectedOutLayersNames();
    if (output_names_.empty() || output_names_.size() > 2)
      throw InputError(model_path, "expected 1 (detect) or 2 (seg) outputs, model has " +
                                       std::to_string(output_names_.size()));
  }
  std::string name() const override { return "onnx-yolo"; }
  std::string model_sha256() const override { return model_.sha256; }
  bool needs_image() const override { return true; }

  FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) override {
    RequireBgrImage(bgr, stamp_text, "onnx-yolo");
    const Letterbox lb = ComputeLetterbox(bgr.cols, bgr.rows, options_.yolo_input_size);
    const cv::Mat blob = cv::dnn::blobFromImage(ApplyLetterbox(bgr, lb), 1.0 / 255.0, cv::Size(), cv::Scalar(),
                                                /*swapRB=*/true, /*crop=*/false);
    model_.net.setInput(blob);
    std::vector<cv::Mat> outs;
    try {
      model_.net.forward(outs, output_names_);
    } catch (const cv::Exception& e) {
      throw InputError(model_.path, "forward failed (export at opset <= 12 with the input size " +
                                        std::to_string(options_.yolo_input_size) + "?): " + e.msg);
    }
    // Predictions are the 3-D output, prototypes (seg models) the 4-D one.
    const cv::Mat* pred_blob = nullptr;
    const cv::Mat* protos = nullptr;
    for (const cv::Mat& o : outs) (o.dims == 4 ? protos : pred_blob) = &o;
    if (!pred_blob) throw InputError(model_.path, "no [1, C, A] prediction output");
    try {
      const YoloPredictions pred =
          ArrangeYoloPredictions(*pred_blob, options_.yolo_input_size, protos ? protos->size[1] : 0);
      const std::vector<std::string> names =
          !class_names_.empty() ? class_names_ : (pred.num_classes == 80 ? CocoClassNames() : std::vector<std::string>{});
      if (!class_names_.empty() && int(class_names_.size()) != pred.num_classes)
        throw InputError(options_.class_names_file, "has " + std::to_string(class_names_.size()) +
                                                        " names, the model " + std::to_string(pred.num_classes) + " classes");
      const std::vector<Candidate> kept =
          PerClassNms(DecodeYoloBoxes(pred, lb, threshold_), options_.nms_iou, options_.max_detections);
      FrameDetections frame = CandidatesToFrame(kept, stamp_text, names);
      if (protos && options_.masks && !kept.empty())
        PaintInstanceMasks(kept, bgr.size(), [&](const Candidate& c) { return DecodeYoloMask(pred, *protos, c, lb); },
                           frame);
      return frame;
    } catch (const std::invalid_argument& e) {
      throw InputError(model_.path, std::string("unexpected YOLO output: ") + e.what());
    }
  }

 private:
  DetectSourceOptions options_;
  LoadedModel model_;
  double threshold_ = kYoloDefaultThreshold;
  std::vector<std::string> class_names_;
  std::vector<std::string> output_names_;
};

}  // namespace

std::unique_ptr<DetectionSource> MakeOnnxYoloSource(const std::string& model_path,
                                                    const DetectSourceOptions& options) {
  return std::make_unique<OnnxYoloSource>(model_path, options);
}

}  // namespace dynref::detect
