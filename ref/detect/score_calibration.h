// How a detection source's confidences relate to the papers' detectors (issue 39). A paper's
// confidence threshold (YOLO conf > 0.5, SparseInst score 0.5, ultralytics' default 0.25) is a
// point on *its* detector's score scale; the embedded NanoDet scores the same real people far
// lower (0.31-0.56 on TUM fr3 walking_halfsphere). Each source therefore declares the threshold
// on its own scale that corresponds to a paper threshold, as a monotone piecewise-linear map from
// (0, 0) to (1, 1) through measured anchor points. Stages compare a detection's raw confidence
// with EquivalentThreshold(paper threshold) unless the config asks for the raw value
// (`threshold_scale: raw`). The numbers and their data: reports/real_people.md.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace dynref::detect {

struct ScoreCalibration {
  std::string name;   // "identity" or the calibrated detector
  std::string basis;  // one line: what data the anchors come from
  // (paper-detector threshold, equivalent threshold of this source), strictly increasing in
  // both, without the implied end points (0, 0) and (1, 1). Empty = identity.
  std::vector<std::pair<double, double>> anchors;
  bool identity() const { return anchors.empty(); }
  // The threshold on this source's scale equivalent to `paper_threshold` (in [0, 1]).
  double EquivalentThreshold(double paper_threshold) const;
};

// The calibration of the source named in a detections folder (`format.txt` `source`, or
// DetectionSource::name()): "nanodet+selfie" and "nanodet" are calibrated; every other source
// (synthetic:*, onnx-yolo = the papers' YOLO family, labels, hog, unknown) is identity.
const ScoreCalibration& CalibrationForSource(const std::string& source_name);

// How a stage reads its min_confidence key: kDetector = the paper's threshold for its detector,
// mapped through the source's calibration (default); kRaw = the number as printed in the paper.
enum class ThresholdScale { kDetector, kRaw };
// "detector" | "raw"; std::invalid_argument otherwise.
ThresholdScale ParseThresholdScale(const std::string& text);

// The threshold a stage applies to raw confidences of detections from `source_name`.
double StageThreshold(double paper_threshold, ThresholdScale scale, const std::string& source_name);

}  // namespace dynref::detect
