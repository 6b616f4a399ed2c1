// Detections against hand-made boxes (issue 39): instance recall and precision at an IoU
// threshold, and the score distribution per class of a detections folder (`dynref info DIR`).
// File format of hand boxes: datasets/real/tum_fr3_walking_halfsphere_10rgb_person_boxes.txt.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "io/mask_format.h"

namespace dynref::detect {

struct HandBox {
  std::string stamp_text, class_name, label;
  double x_min = 0, y_min = 0, x_max = 0, y_max = 0;  // inclusive pixels
};

// "# ..." comments; lines "rgb_stamp class label x_min y_min x_max y_max". InputError (file,
// line) on a malformed line or max < min.
std::vector<HandBox> ReadHandBoxes(const std::string& path);

struct MatchCounts {
  int truth = 0;       // hand boxes of the class
  int detections = 0;  // detections of the class with confidence >= min_confidence
  int matched = 0;     // one-to-one matches with IoU >= iou
  double Recall() const { return truth ? double(matched) / truth : 0.0; }
  double Precision() const { return detections ? double(matched) / detections : 0.0; }
};

// Intersection over union of two inclusive pixel boxes.
double InclusiveBoxIou(double ax0, double ay0, double ax1, double ay1, double bx0, double by0, double bx1,
                       double by1);

// Per frame: detections of `class_name` with confidence >= min_confidence, in descending
// confidence (ties: ascending id), each matched greedily to the unmatched hand box of highest
// IoU (ties: first in the file) when that IoU >= iou. Frames without detections count their
// hand boxes as missed.
MatchCounts MatchAgainstHandBoxes(const std::map<std::string, FrameDetections>& frames,
                                  const std::vector<HandBox>& truth, const std::string& class_name,
                                  double min_confidence, double iou);

// Score distribution per class name over frames: count, min, quartiles, max, and counts at or
// above each of `cuts` (printed by `dynref info DETECTIONS_DIR`).
struct ScoreSummary {
  int count = 0;
  double min = 0, q25 = 0, median = 0, q75 = 0, max = 0;
  std::vector<int> at_least;  // one per cut
};
std::map<std::string, ScoreSummary> SummariseScores(const std::map<std::string, FrameDetections>& frames,
                                                    const std::vector<double>& cuts);

}  // namespace dynref::detect
