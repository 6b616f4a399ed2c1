// seed 003 Sec. 3.3, probability-based detection and elimination. Pre-defined probability
// (Eq. 20): P(x_i) = 1 inside the fused, dilated mask M_sd, else 0. Each keypoint with P = 0 is
// re-scored from its neighbours within radius D (k-d tree over keypoint pixels, all keypoints,
// the keypoint itself excluded):
//   P'(x_i) = (1/n) * sum_k lambda(r_k) * P(x_k),  lambda(r) = c1 * exp(-c2 * r),  n = |X_i|,
// with the pre-defined P on the right-hand side (order independent, spec E8), P' = 0 when n = 0.
// A keypoint is dynamic when its final probability is > theta (E9: exactly theta is static).
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace dynref::blur {

struct KeypointProbabilityOptions {
  double radius_px = 20;   // D (not stated)
  double c1 = 1.0;         // lambda scale (not stated)
  double c2 = 0.05;        // lambda rate, 1/px (not stated)
  double theta = 0.5;      // dynamic threshold (not stated)
  bool compute = true;     // false = "w/o probability": dynamic iff in M_sd
  void Check() const;      // std::invalid_argument naming the field
};

struct KeypointProbability {
  double pre = 0;          // Eq. (20)
  double post = 0;         // final probability (pre for mask keypoints, P' otherwise)
  int neighbours = 0;      // n
  int dynamic_neighbours = 0;  // neighbours with P = 1
  bool dynamic = false;
};

std::vector<KeypointProbability> KeypointProbabilities(const std::vector<cv::Point2f>& points,
                                                       const std::vector<uint8_t>& in_mask,
                                                       const KeypointProbabilityOptions& o);

}  // namespace dynref::blur
