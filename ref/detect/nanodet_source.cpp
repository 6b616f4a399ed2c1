// `nanodet` source: bundled NanoDet (COCO-80, GFL head) on OpenCV DNN, per-class NMS, then
// selfie person masks on enlarged square crops (models/README.md). Non-person classes are
// box-only instances.
#include <opencv2/dnn.hpp>
#include <optional>

#include "core/error.h"
#include "detect/nanodet_decode.h"
#include "detect/onnx_model.h"
#include "detect/person_masker.h"
#include "detect/sources.h"

namespace dynref::detect {
namespace {

constexpr int kNanodetInput = 416;
constexpr double kNanodetDefaultThreshold = 0.3;  // models/README.md, "Decoding NanoDet"

class NanodetSource : public DetectionSource {
 public:
  explicit NanodetSource(const DetectSourceOptions& options) : options_(options) {
    const bool bundled = options.model_path.empty();
    const std::string path = bundled ? BundledModelPath("nanodet.onnx") : options.model_path;
    // A user-supplied NanoDet export must be named by its hash (the decoding assumes this head).
    const std::string expected = options.model_sha256.empty() ? kNanodetSha256 : options.model_sha256;
    detector_ = LoadOnnxModel(path, expected, "NanoDet");
    if (options.masks) {
      const std::string mpath = options.mask_model_path.empty() ? BundledModelPath("selfie.onnx")
                                                                : options.mask_model_path;
      masker_.emplace(LoadOnnxModel(mpath, kSelfieSha256, "selfie segmenter"));
    }
    threshold_ = options.confidence_threshold >= 0 ? options.confidence_threshold : kNanodetDefaultThreshold;
  }

  std::string name() const override { return masker_ ? "nanodet+selfie" : "nanodet"; }
  std::string model_sha256() const override {
    return masker_ ? detector_.sha256 + "+" + masker_->sha256() : detector_.sha256;
  }
  bool needs_image() const override { return true; }

  FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) override {
    RequireBgrImage(bgr, stamp_text, "nanodet");
    // Plain resize to 416x416, RGB, pixel / 255 (models/README.md).
    const cv::Mat blob = cv::dnn::blobFromImage(bgr, 1.0 / 255.0, cv::Size(kNanodetInput, kNanodetInput),
                                                cv::Scalar(), /*swapRB=*/true, /*crop=*/false);
    detector_.net.setInput(blob);
    std::vector<cv::Mat> outs;
    static const std::vector<std::string> kOutputs = {"Identity",   "Identity_1", "Identity_2",
                                                      "Identity_3", "Identity_4", "Identity_5"};
    try {
      detector_.net.forward(outs, kOutputs);
    } catch (const cv::Exception& e) {
      throw InputError(detector_.path, "NanoDet forward failed (not the expected outputs Identity..Identity_5?): " + e.msg);
    }
    std::vector<NanodetLevel> levels = {{8, outs[0], outs[3]}, {16, outs[1], outs[4]}, {32, outs[2], outs[5]}};
    NanodetDecodeOptions d;
    d.input_size = kNanodetInput;
    d.score_threshold = threshold_;
    d.image_width = bgr.cols;
    d.image_height = bgr.rows;
    std::vector<Candidate> candidates;
    try {
      candidates = DecodeNanodet(levels, d);
    } catch (const std::invalid_argument& e) {
      throw InputError(detector_.path, std::string("unexpected NanoDet output: ") + e.what());
    }
    const std::vector<Candidate> kept = PerClassNms(std::move(candidates), options_.nms_iou, options_.max_detections);
    FrameDetections frame = CandidatesToFrame(kept, stamp_text, CocoClassNames());
    if (masker_) masker_->AddMasks(bgr, frame);
    return frame;
  }

 private:
  DetectSourceOptions options_;
  LoadedModel detector_;
  std::optional<PersonMasker> masker_;
  double threshold_ = kNanodetDefaultThreshold;
};

}  // namespace

std::unique_ptr<DetectionSource> MakeNanodetSource(const DetectSourceOptions& options) {
  return std::make_unique<NanodetSource>(options);
}

}  // namespace dynref::detect
