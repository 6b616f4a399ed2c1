// Per-source score calibration (issue 39): identity for synthetic / YOLO sources (the synthetic
// tables must not move), NanoDet's measured map, and the raw switch.
#include <catch2/catch.hpp>

#include "detect/score_calibration.h"

using namespace dynref::detect;

TEST_CASE("detect: synthetic, YOLO, label and unknown sources keep the paper's threshold") {
  for (const char* source : {"synthetic:yolo-like", "synthetic:sparseinst-like", "synthetic:ideal", "synthetic:gt",
                             "onnx-yolo", "hog", "labels", ""}) {
    INFO(source);
    const ScoreCalibration& c = CalibrationForSource(source);
    CHECK(c.identity());
    for (double t : {0.0, 0.25, 0.5, 0.7, 1.0}) CHECK(c.EquivalentThreshold(t) == t);
    CHECK(StageThreshold(0.5, ThresholdScale::kDetector, source) == 0.5);
  }
}

TEST_CASE("detect: NanoDet's calibration is monotone, fixes 0 and 1, and lowers the papers' thresholds") {
  for (const char* source : {"nanodet+selfie", "nanodet"}) {
    const ScoreCalibration& c = CalibrationForSource(source);
    REQUIRE_FALSE(c.identity());
    CHECK(c.EquivalentThreshold(0.0) == 0.0);
    CHECK(c.EquivalentThreshold(1.0) == 1.0);
    double last = -1;
    for (int i = 0; i <= 100; ++i) {
      const double v = c.EquivalentThreshold(i / 100.0);
      CHECK(v > last);
      last = v;
    }
    for (const auto& [paper, own] : c.anchors) CHECK(c.EquivalentThreshold(paper) == own);
    CHECK(c.EquivalentThreshold(0.5) < 0.5);
    CHECK(c.EquivalentThreshold(0.25) < 0.25);
    // The raw switch: the number as printed in the paper.
    CHECK(StageThreshold(0.5, ThresholdScale::kRaw, source) == 0.5);
  }
  CHECK(ParseThresholdScale("detector") == ThresholdScale::kDetector);
  CHECK(ParseThresholdScale("raw") == ThresholdScale::kRaw);
  CHECK_THROWS_AS(ParseThresholdScale("calibrated"), std::invalid_argument);
  CHECK_THROWS_AS(CalibrationForSource("nanodet").EquivalentThreshold(1.5), std::invalid_argument);
}
