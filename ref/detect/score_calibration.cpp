#include "detect/score_calibration.h"

#include <stdexcept>

namespace dynref::detect {

double ScoreCalibration::EquivalentThreshold(double paper_threshold) const {
  if (!(paper_threshold >= 0 && paper_threshold <= 1)) throw std::invalid_argument("paper threshold must be in [0, 1]");
  double x0 = 0, y0 = 0;
  std::vector<std::pair<double, double>> pts = anchors;
  pts.push_back({1.0, 1.0});
  for (const auto& [x1, y1] : pts) {
    if (paper_threshold <= x1) return x1 == x0 ? y1 : y0 + (y1 - y0) * (paper_threshold - x0) / (x1 - x0);
    x0 = x1;
    y0 = y1;
  }
  return 1.0;
}

namespace {

ScoreCalibration Identity() {
  return {"identity", "synthetic and YOLO-family sources are modelled on the papers' detectors; others are not calibrated", {}};
}

// NanoDet-m (COCO, 416 input) + selfie, measured on the 10 real frames of TUM fr3
// walking_halfsphere against 20 hand-drawn person boxes
// (datasets/real/tum_fr3_walking_halfsphere_10rgb_person_boxes.txt), reports/real_people.md.
ScoreCalibration Nanodet() {
  // Paper 0.5 -> 0.25: the lowest NanoDet score with person precision >= 0.8 (0.80, recall 0.60);
  // paper 0.25 -> 0.10: where NanoDet's person recall reaches its plateau (0.90, precision 0.44).
  return {"nanodet",
          "person precision >= 0.8 at 0.25 and the recall plateau at 0.10 on 20 hand-boxed persons, 10 real TUM fr3 "
          "walking_halfsphere frames (reports/real_people.md)",
          {{0.25, 0.10}, {0.5, 0.25}}};
}

}  // namespace

const ScoreCalibration& CalibrationForSource(const std::string& source_name) {
  static const ScoreCalibration kIdentity = Identity();
  static const ScoreCalibration kNanodet = Nanodet();
  if (source_name == "nanodet+selfie" || source_name == "nanodet") return kNanodet;
  return kIdentity;
}

ThresholdScale ParseThresholdScale(const std::string& text) {
  if (text == "detector") return ThresholdScale::kDetector;
  if (text == "raw") return ThresholdScale::kRaw;
  throw std::invalid_argument("threshold_scale must be 'detector' or 'raw', got '" + text + "'");
}

double StageThreshold(double paper_threshold, ThresholdScale scale, const std::string& source_name) {
  if (scale == ThresholdScale::kRaw) return paper_threshold;
  return CalibrationForSource(source_name).EquivalentThreshold(paper_threshold);
}

}  // namespace dynref::detect
