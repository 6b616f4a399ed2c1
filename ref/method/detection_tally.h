// A stage's count of the detections it used and dropped (issue 39): the threshold a paper states
// for its detector, mapped to the run's detection source (detect/score_calibration.h) unless the
// config asks for the raw value, and the run totals reported through RunEnd::AddDetectionUse.
#pragma once
#include <cstdio>
#include <string>
#include <vector>

#include "detect/score_calibration.h"
#include "io/mask_format.h"
#include "method/params.h"
#include "method/run_end.h"
#include "trace/trace_writer.h"

namespace dynref {

class DetectionTally {
 public:
  // `key` is the stage's threshold key (its value is the paper's threshold); the scale is read
  // from the stage's `threshold_scale` key ("detector" | "raw").
  DetectionTally(std::string stage, const ParamMap& p, const std::string& key = "min_confidence")
      : DetectionTally(stage, stage + "." + key, p.GetDouble(key), p.GetString("threshold_scale")) {}
  // `key` in full ("mgd.probability.min_confidence"): what a user sets with --set.
  DetectionTally(std::string stage, const std::string& key, double paper_threshold, const std::string& scale) {
    use_.stage = std::move(stage);
    use_.key = key;
    use_.paper_threshold = paper_threshold;
    use_.scale = scale;
    scale_ = detect::ParseThresholdScale(scale);  // std::invalid_argument (the spec checks the choice first)
    use_.applied_threshold = paper_threshold;
  }
  // The threshold to compare this frame's raw confidences with.
  double Threshold(const FrameDetections& det) {
    if (det.source != use_.source || !started_) {
      use_.source = det.source;
      use_.applied_threshold = detect::StageThreshold(use_.paper_threshold, scale_, det.source);
      started_ = true;
    }
    return use_.applied_threshold;
  }
  // One detection of a dynamic class; `dropped` when below the threshold.
  void Count(bool dropped) {
    ++use_.seen;
    use_.dropped += dropped ? 1 : 0;
  }
  void Report(RunEnd& end) const { end.AddDetectionUse(use_); }
  // The inputs of an instance's mask record (issue 32: `trace verify` recomputes the decision):
  // class and confidence, plus the threshold applied when the source's calibration moved it off
  // the paper's number (absent otherwise, so traces of uncalibrated sources are unchanged).
  std::vector<trace::NamedValue> InstanceInputs(const DetectedInstance& inst) const {
    std::vector<trace::NamedValue> in = {{"class_id", static_cast<double>(inst.class_id)}, {"confidence", inst.confidence}};
    if (use_.applied_threshold != use_.paper_threshold) in.push_back({"applied_min_confidence", use_.applied_threshold});
    return in;
  }
  const DetectionUse& use() const { return use_; }

 private:
  DetectionUse use_;
  detect::ThresholdScale scale_ = detect::ThresholdScale::kDetector;
  bool started_ = false;
};

// "blur.mask 12 seen, 3 dropped (< 0.300 = paper 0.5 on nanodet+selfie)": the end-of-run line.
inline std::string DetectionUseText(const DetectionUse& u) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.3f", u.applied_threshold);
  std::string t = u.stage + " " + std::to_string(u.seen) + " seen, " + std::to_string(u.dropped) + " dropped (< " + buf;
  if (u.applied_threshold != u.paper_threshold || u.scale == "raw") {
    std::snprintf(buf, sizeof(buf), "%g", u.paper_threshold);
    t += std::string(" = paper ") + buf + (u.scale == "raw" ? " raw" : "");
  }
  return t + (u.source.empty() ? "" : " on " + u.source) + ")";
}

// The warning when a stage dropped most of the detections it saw (empty when it did not).
inline std::string DetectionUseWarning(const DetectionUse& u) {
  if (!u.MostDropped()) return "";
  const std::string stage_key = u.key.substr(0, u.key.rfind('.'));
  return u.stage + " dropped " + std::to_string(u.dropped) + " of " + std::to_string(u.seen) +
         " dynamic-class detections below its confidence threshold (" + DetectionUseText(u) + "); lower " + u.key +
         (u.scale == "raw" ? " or set " + stage_key + ".threshold_scale=detector" : "") +
         " (dynref run --set), or check the scores with dynref info DETECTIONS_DIR";
}

}  // namespace dynref
