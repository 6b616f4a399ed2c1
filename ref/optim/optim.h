// Optimisation room: ORB-SLAM2's Optimizer::PoseOptimization and Optimizer::LocalBundleAdjustment
// re-implemented with Ceres on plain structs (no dependency on the map/tracking classes).
//
// Conventions shared by both calls (ORB-SLAM2 Optimizer.cc, g2o edges in types_six_dof_expmap):
// - Residual = observation - projection, with projection u = fx x/z + cx, v = fy y/z + cy of the
//   camera point X_c = T_cw X_w, and for RGB-D ("stereo") observations the virtual right
//   coordinate u_r = u - bf/z. RGB-D residuals are 3-dof ("rgbd3"), monocular ones 2-dof ("mono2").
// - Information = inv_sigma2 * weight * I (inv_sigma2 of the keypoint octave; weight is a
//   dynamic method's per-observation weight, e.g. SGDO's omega, 0..1). Implemented as whitening:
//   the Ceres residual is sqrt(inv_sigma2 * weight) * (obs - proj).
// - chi2 = e^T Info e (no robust loss). Outlier test: chi2 > 7.815 (rgbd3) / 5.991 (mono2), the
//   95 % chi-square quantiles for 3 / 2 dof. A weight-0 observation has chi2 = 0 and no influence.
// - Huber loss with delta = sqrt(threshold) on the whitened residual, as g2o's RobustKernelHuber.
// - Determinism: Ceres num_threads = 1, fixed dense solvers, residual blocks added in input order.
//
// Trace (when trace != nullptr && trace->full_enabled()): one Residual record per input
// observation, in input order, with the raw (unwhitened) residual at the start and at the end of
// the call, information = inv_sigma2, the weight, robust_loss = Huber rho(chi2) at the end state
// (rho(s) = s for s <= delta^2, 2 delta sqrt(s) - delta^2 otherwise), chi2 at the end and the
// returned inlier flag.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/intrinsics.h"
#include "core/se3.h"

namespace dynref::trace {
class TraceWriter;
}

namespace dynref::optim {

// The shared pinhole type (core/intrinsics.h); bf (ORB-SLAM2 Camera.bf = baseline * fx) is only
// used through u_right.
using Intrinsics = dynref::Intrinsics;

// One observation of a fixed 3-D point in the camera being optimised.
struct PoseObservation {
  Eigen::Vector3d X_w = Eigen::Vector3d::Zero();  // fixed world point
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();   // undistorted keypoint (px)
  double u_right = -1;    // ORB-SLAM2 virtual right coordinate u - bf/depth; < 0 => mono2 residual
  double inv_sigma2 = 1;  // 1/sigma^2 of the keypoint octave (ORB-SLAM2 information)
  double weight = 1;      // method weight multiplying the information, 0..1
  std::string obs_id;     // trace id, e.g. "mp17@f42"
};

struct PoseOnlyOptions {
  int rounds = 4;       // ORB-SLAM2: 4 optimisations of 10 iterations each
  int iterations = 10;  // LM iterations per round
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int min_edges = 10;  // stop after a round that leaves fewer inliers than this (ORB-SLAM2: 10)
  // ORB-SLAM2 re-sets the estimate to the initial pose before each round (only the inlier set
  // carries over); false = continue from the previous round's estimate.
  bool restart_each_round = true;
  // Outlier test on inv_sigma2 * weight instead of inv_sigma2 (see MakeEdgeModel, issue 21).
  bool weighted_outlier_test = false;
  void Check() const;  // throws InputError naming the bad field
};

struct PoseOnlyResult {
  SE3 T_cw = SE3::Identity();
  std::vector<uint8_t> inlier;  // per input observation (1 = inlier)
  std::vector<double> chi2;     // per input observation at the returned pose (+inf: behind camera)
  int num_inliers = 0;
  int rounds_run = 0;  // rounds actually optimised (early stop when < min_edges remain)
};

// ORB-SLAM2 Optimizer::PoseOptimization: `rounds` LM solves of `iterations` iterations, each from
// T_cw_init (see restart_each_round); after each round every observation is re-classified by chi2
// (outliers are excluded from the next round but re-tested after it, so they can come back); the
// robust kernel is dropped in the last round; stops early when fewer than min_edges inliers remain.
// Observations whose point is not in front of the camera (z <= 0) are outliers. With fewer than 3
// observations the pose is returned unchanged (ORB-SLAM2: nInitialCorrespondences < 3).
PoseOnlyResult OptimizePose(const Intrinsics& K, const SE3& T_cw_init,
                            const std::vector<PoseObservation>& observations,
                            const PoseOnlyOptions& options, trace::TraceWriter* trace,
                            const std::string& call_id);

struct BAKeyFrame {
  int64_t id = 0;
  SE3 T_cw = SE3::Identity();
  bool fixed = false;
};
struct BAPoint {
  int64_t id = 0;
  Eigen::Vector3d X_w = Eigen::Vector3d::Zero();
};
struct BAObservation {
  int64_t kf_id = 0;
  int64_t point_id = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double u_right = -1;
  double inv_sigma2 = 1;
  double weight = 1;
};

struct LocalBAOptions {
  int iterations_robust = 5;   // ORB-SLAM2: optimize(5) with Huber
  int iterations_refine = 10;  // ORB-SLAM2: optimize(10) without robust kernel, outliers removed
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  bool weighted_outlier_test = false;  // as PoseOnlyOptions
  void Check() const;
};

struct LocalBAResult {
  std::map<int64_t, SE3> T_cw;             // every input keyframe (fixed ones unchanged)
  std::map<int64_t, Eigen::Vector3d> X_w;  // every input point
  std::vector<uint8_t> inlier;             // per input observation; 0 = outlier to erase
  std::vector<double> chi2;                // per input observation at the final estimate
  int num_inliers = 0;
};

// ORB-SLAM2 Optimizer::LocalBundleAdjustment on given keyframes/points/observations: fixed
// keyframes are constant, points are free. iterations_robust LM iterations with Huber, then
// observations with chi2 > threshold or the point behind the camera are dropped, then
// iterations_refine iterations without robust kernel; final flags: inlier = not dropped and
// chi2 <= threshold and depth > 0 at the final estimate. Observations referring to unknown
// keyframe/point ids throw InputError.
LocalBAResult LocalBundleAdjust(const Intrinsics& K, const std::vector<BAKeyFrame>& keyframes,
                                const std::vector<BAPoint>& points,
                                const std::vector<BAObservation>& observations,
                                const LocalBAOptions& options, trace::TraceWriter* trace,
                                const std::string& call_id);

}  // namespace dynref::optim
