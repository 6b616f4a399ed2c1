// `onnx-maskrcnn` and `onnx-yolact` sources: a user's torchvision Mask R-CNN or YOLACT instance
// segmenter exported to ONNX and run through OpenCV DNN; layouts and their sources in
// maskrcnn_decode.h and yolact_decode.h. Classes are COCO's (Mask R-CNN's 91-id labels, YOLACT's
// 80 columns after the background); other class counts come out as class_<k>.
#include <opencv2/dnn.hpp>
#include <functional>
#include <stdexcept>

#include "core/error.h"
#include "detect/maskrcnn_decode.h"
#include "detect/onnx_model.h"
#include "detect/sources.h"
#include "detect/yolact_decode.h"

namespace dynref::detect {
namespace {

// Both exports already drop candidates under 0.05 (torchvision box_score_thresh, YOLACT's
// Detect conf_thresh); the methods apply their own thresholds on top.
constexpr double kInstanceDefaultThreshold = 0.05;

std::vector<cv::Mat> Forward(LoadedModel& model, const cv::Mat& blob, const std::vector<std::string>& names,
                             const std::string& kind) {
  model.net.setInput(blob);
  std::vector<cv::Mat> outs;
  try {
    model.net.forward(outs, names);
  } catch (const cv::Exception& e) {
    throw InputError(model.path, kind + " forward failed (is this a " + kind + " export OpenCV DNN can run?): " + e.msg);
  }
  return outs;
}

// Instances from kept candidates, with their masks (PaintInstanceMasks, as onnx-yolo).
FrameDetections ToFrame(const std::vector<Candidate>& kept, const std::string& stamp_text, cv::Size image,
                        bool masks, const std::function<cv::Mat(const Candidate&)>& mask_of) {
  FrameDetections frame = CandidatesToFrame(kept, stamp_text, CocoClassNames());
  if (masks && !kept.empty()) PaintInstanceMasks(kept, image, mask_of, frame);
  return frame;
}

class OnnxInstanceSource : public DetectionSource {
 public:
  OnnxInstanceSource(const std::string& kind, const std::string& model_path, const DetectSourceOptions& options)
      : kind_(kind), options_(options) {
    model_ = LoadOnnxModel(model_path, options.model_sha256, kind == "onnx-yolact" ? "YOLACT" : "Mask R-CNN");
    threshold_ = options.confidence_threshold >= 0 ? options.confidence_threshold : kInstanceDefaultThreshold;
    output_names_ = model_.net.getUnconnectedOutLayersNames();
    if (kind_ == "onnx-yolact") {
      // --input-size: its default (640, onnx-yolo's) stands for YOLACT's 550 (yolact_base).
      layout_ = YolactLayoutForInput(options.yolo_input_size == 640 ? 550 : options.yolo_input_size);
      priors_ = YolactPriors(layout_);
    }
  }
  std::string name() const override { return kind_; }
  std::string model_sha256() const override { return model_.sha256; }
  bool needs_image() const override { return true; }

  FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) override {
    RequireBgrImage(bgr, stamp_text, kind_);
    try {
      return kind_ == "onnx-yolact" ? DetectYolact(bgr, stamp_text) : DetectMaskRcnn(bgr, stamp_text);
    } catch (const std::invalid_argument& e) {
      throw InputError(model_.path, "unexpected " + kind_ + " output layout: " + e.what());
    }
  }

 private:
  FrameDetections DetectMaskRcnn(const cv::Mat& bgr, const std::string& stamp_text) {
    // torchvision takes RGB in [0, 1] at the frame's size and normalises inside the model.
    const cv::Mat blob = cv::dnn::blobFromImage(bgr, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false);
    const std::vector<cv::Mat> outs = Forward(model_, blob, output_names_, "Mask R-CNN");
    const MaskRcnnOutputs o = ArrangeMaskRcnnOutputs(outs, output_names_);
    const std::vector<Candidate> kept =
        PerClassNms(DecodeMaskRcnnBoxes(o, bgr.size(), threshold_), options_.nms_iou, options_.max_detections);
    return ToFrame(kept, stamp_text, bgr.size(), options_.masks && !o.masks.empty(),
                   [&](const Candidate& c) { return DecodeMaskRcnnMask(o, c.anchor, bgr.size()); });
  }

  FrameDetections DetectYolact(const cv::Mat& bgr, const std::string& stamp_text) {
    const std::vector<cv::Mat> outs = Forward(model_, YolactBlob(bgr, layout_.input_size), output_names_, "YOLACT");
    const YolactOutputs o = ArrangeYolactOutputs(outs, output_names_, priors_.rows);
    const std::vector<Candidate> kept = PerClassNms(DecodeYolactBoxes(o, priors_, bgr.size(), threshold_, layout_),
                                                    options_.nms_iou, options_.max_detections);
    return ToFrame(kept, stamp_text, bgr.size(), options_.masks,
                   [&](const Candidate& c) { return DecodeYolactMask(o, c, bgr.size()); });
  }

  std::string kind_;
  DetectSourceOptions options_;
  LoadedModel model_;
  double threshold_ = kInstanceDefaultThreshold;
  std::vector<std::string> output_names_;
  YolactLayout layout_;
  cv::Mat priors_;
};

}  // namespace

std::unique_ptr<DetectionSource> MakeOnnxInstanceSource(const std::string& kind, const std::string& model_path,
                                                        const DetectSourceOptions& options) {
  return std::make_unique<OnnxInstanceSource>(kind, model_path, options);
}

}  // namespace dynref::detect
