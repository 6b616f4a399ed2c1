// seed 001, Sec. 3.3 (first step): correspondences between frame k-1 and k by pyramidal
// Lucas-Kanade flow [44], and the DS-SLAM style [19] pruning of pairs unfit for estimating F.
// spec 001 E2: flow runs on the current ORB keypoints, tracked BACKWARDS into k-1, so every
// current keypoint gets at most one pair (P1 in k-1, P2 = the keypoint in k).
#pragma once
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "io/camera.h"

namespace dynref::geometry {

struct LkOptions {
  int window_px = 21;   // not stated: OpenCV default
  int max_level = 3;    // not stated: OpenCV default (pyramid levels 0..3)
  int max_iterations = 30;  // OpenCV default criteria (COUNT|EPS, 30, 0.01)
  double epsilon = 0.01;
  int border_px = 5;          // b_edge, not stated: DS-SLAM limit_edge_corner
  double patch_sad_max = 2120;  // c_patch on a 3x3 grey patch, not stated: DS-SLAM limit_of_check
  // Not a parameter: the run's --threads. The points are tracked in that many slices side by
  // side (each point's flow depends on the images and the point only, so the pairs are the same
  // for every count; each slice builds its own pyramids).
  int threads = 1;
  void Check() const;
};

// Why a pair was kept out of F estimation ("" = usable). A pair with `tracked` = true still gets
// its epipolar distance even when pruned (pruning only concerns the F estimate, spec 001 E2).
struct LkPair {
  cv::Point2f p_prev;   // P1 in frame k-1
  cv::Point2f p_cur;    // P2 = the current keypoint
  bool tracked = false; // LK converged and P1 lies inside the previous image
  std::string prune_reason;  // "" | "lk-failed" | "border" | "patch-sad" | "in-mask"
  double patch_sad = 0;      // 3x3 SAD (0 when not computed)
  bool usable_for_F() const { return tracked && prune_reason.empty(); }
};

// Tracks `points_cur` from cur_grey back into prev_grey (both CV_8U, same size). No RNG;
// deterministic given cv::setNumThreads(0), and the same for any options.threads.
std::vector<LkPair> TrackBackward(const cv::Mat& prev_grey, const cv::Mat& cur_grey,
                                  const std::vector<cv::Point2f>& points_cur,
                                  const LkOptions& options);

// 3x3 sum of absolute grey differences between the patches centred at the (truncated, as
// DS-SLAM) integer positions of p_prev and p_cur. Both centres must be >= 1 px inside.
double PatchSad3x3(const cv::Mat& prev_grey, const cv::Mat& cur_grey, cv::Point2f p_prev,
                   cv::Point2f p_cur);

// Pruning of one tracked pair (spec 001 step 3b): border (either point within border_px of an
// edge), appearance (SAD > patch_sad_max), then `in_mask` (P2 in M). Sets prune_reason/patch_sad.
void PrunePair(const cv::Mat& prev_grey, const cv::Mat& cur_grey, bool in_mask,
               const LkOptions& options, LkPair& pair);

// Both ends of every pair on undistorted pixels (cv::undistortPoints, K kept) for F, epipolar
// distances and poses; a copy of the pixels when the camera has no distortion (TUM fr3, synthetic).
void UndistortedPairPixels(const Camera& camera, const std::vector<LkPair>& pairs, std::vector<cv::Point2f>* prev,
                           std::vector<cv::Point2f>* cur);

}  // namespace dynref::geometry
