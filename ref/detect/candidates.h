// Raw detector candidates (before and after non-maximum suppression) and the helpers every
// network source shares: IoU, deterministic per-class NMS, conversion to dynref instances.
#pragma once
#include <vector>

#include "io/mask_format.h"

namespace dynref::detect {

struct Candidate {
  int class_id = -1;            // network class index
  double score = 0;             // in [0, 1]
  double x_min = 0, y_min = 0, x_max = 0, y_max = 0;  // image pixels
  int anchor = 0;               // index of the anchor/cell it came from (tie-break, mask coeffs)
};

double BoxIou(const Candidate& a, const Candidate& b);

// Per-class greedy NMS: within each class, candidates in descending score (ties: ascending
// anchor) suppress later ones with IoU > iou_threshold. The survivors of all classes are returned
// in descending score, ties by ascending class id then anchor, at most max_detections of them.
// Deterministic: the result never depends on the input order of equal-score candidates with
// distinct anchors.
std::vector<Candidate> PerClassNms(std::vector<Candidate> candidates, double iou_threshold,
                                   int max_detections);

// Clips a box to [0, width] x [0, height].
void ClipBox(Candidate& c, int width, int height);

// dynref instance for a COCO-80 candidate (ids assigned by the caller).
DetectedInstance ToCocoInstance(const Candidate& c, int id);

}  // namespace dynref::detect
