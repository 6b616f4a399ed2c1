// seed 004 Module C (Sec. 3.3.1), steps 5c-5e: a prior-dynamic mask is dynamic when more than
// vote_ratio (60 %) of its matched keypoints violate the epipolar constraint (distance > eps);
// a mask without any matched keypoint is dynamic (spec 004 E8, conservative: it is a
// prior-dynamic class). Static-class masks never take part (E6).
#pragma once
#include <Eigen/Core>
#include <map>
#include <vector>

namespace dynref::epi {

struct MaskVoteOptions {
  double epi_threshold_px = 1.0;  // eps_epi (not stated: DS-SLAM public code)
  double vote_ratio = 0.6;        // paper Sec. 3.3.1: more than 60 %
  void Check() const;             // std::invalid_argument naming the field
};

struct MaskVote {
  int matched = 0;      // keypoints of the mask with an epipolar distance
  int violating = 0;    // of them with distance > eps
  double ratio = 0;     // violating / matched (0 when none matched)
  bool dynamic = true;
};

// instance_of[i]: mask instance of keypoint i (0 = static region); distance[i]: its epipolar
// distance, NaN when it has no match. Returns one vote per instance id > 0 that owns a keypoint,
// plus every id of `masks` (masks without keypoints are voted too).
std::map<int, MaskVote> VoteMasks(const std::vector<int>& instance_of, const std::vector<double>& distance,
                                  const std::vector<int>& masks, const MaskVoteOptions& o);

// Eq. (14): distance of p_cur to the epipolar line F p_prev, F = K^-T [t]x R K^-1 (Eq. (12)), with
// (R, t) = T_cur_prev. With t = 0 F vanishes and has no line; as t -> 0 the line passes through
// H p_prev, H = K R K^-1 (rotation-only homography), so the distance is |p_cur - H p_prev| there
// (issue 38: +inf made every in-mask keypoint of a still camera a violation). A point at the
// epipole (zero line, t != 0) gives no evidence: NaN. F or H is built once per frame.
class VoteGeometry {
 public:
  VoteGeometry(const Eigen::Matrix3d& K, const Eigen::Matrix3d& R, const Eigen::Vector3d& t);
  double Distance(const Eigen::Vector2d& p_prev, const Eigen::Vector2d& p_cur) const;

 private:
  bool still_;        // t = 0: H instead of F
  Eigen::Matrix3d M_; // F, or H when still_
};

// VoteGeometry(K, R, t).Distance(p_prev, p_cur), for one pair.
double VoteDistance(const Eigen::Matrix3d& K, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                    const Eigen::Vector2d& p_prev, const Eigen::Vector2d& p_cur);

}  // namespace dynref::epi
