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
// Link records (ref/optim/README.md "Trace"): right before each Residual record, when the
// observation carries its frame index (trace_feature / trace_line / trace_plane >= 0), a PROB
// record of stage "<call family>.obs" ("track.pose.obs", "localba.obs") on the residual's
// observation id, p = 0, naming what `dynref trace verify` needs to recompute the residual:
//   pose-only points: feature, x, y, z (the fixed world point);  lines: line;  planes: plane
//   local BA points: feature, robust_chi2 (outlier-test chi2 after the robust phase, +inf when the
//   edge did not enter it);  lines: line, robust_chi2;  planes: plane, robust_chi2
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <array>
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
  int64_t trace_feature = -1;  // frame feature index, written to the residual's link record (-1: none)
};

// Line and plane observations (seed 000, issue 13); residuals and their derivation in
// optim/structure_residuals.h.
struct StructureResidualOptions {
  bool literal_line = false;        // spec E15: the literal scalar e_col + e_par
  double line_sigma_px = 1.0;       // spec 000 (c): Sigma_l = 1 px^2
  double plane_angle_sigma_rad = 0.017453292519943295;  // (1 deg)^2
  double plane_dist_sigma_m = 0.02;                     // (0.02 m)^2
  double chi2_line4 = 9.488;        // 95 % chi2, 4 dof
  double chi2_line1 = 3.841;        // 95 % chi2, 1 dof (spec's Huber delta^2 for lines)
  double chi2_plane = 7.815;        // 95 % chi2, 3 dof
  double LineChi2() const { return literal_line ? chi2_line1 : chi2_line4; }
  int LineDim() const { return literal_line ? 1 : 4; }
  void Check() const;               // InputError naming the field
};

struct LineObservation {
  std::array<Eigen::Vector3d, 3> X_w{};  // samples s, m, e of the map line (fixed in pose-only)
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  Eigen::Vector3d l_companion = Eigen::Vector3d::Zero();
  bool has_companion = false;
  double weight = 1;
  std::string obs_id;  // trace id, e.g. "ml3@f42"
  int64_t trace_line = -1;  // frame line index (link record; -1: none)
};

struct PlaneObservationResidual {
  Eigen::Vector3d n_w = Eigen::Vector3d::UnitZ();  // map plane (fixed in pose-only)
  double d_w = 0;
  Eigen::Vector3d n_obs = Eigen::Vector3d::UnitZ();
  double d_obs = 0;
  double weight = 1;
  std::string obs_id;  // "mpl2@f42"
  int64_t trace_plane = -1;  // frame plane index (link record; -1: none)
};

// The structure part of a pose-only problem (empty: the point-only ORB-SLAM2 problem).
struct PoseStructure {
  std::vector<LineObservation> lines;
  std::vector<PlaneObservationResidual> planes;
  StructureResidualOptions options;
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
  std::vector<uint8_t> line_inlier, plane_inlier;  // per structure observation
  int line_inliers = 0, plane_inliers = 0;
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
// The same with line and plane residuals after the points (issue 13): they share the rounds, the
// robust kernel schedule (Huber delta^2 = their chi2 threshold), the re-classification and the
// min_edges count; the 3-observation minimum counts them too. structure == nullptr or empty
// gives exactly the point-only call.
PoseOnlyResult OptimizePose(const Intrinsics& K, const SE3& T_cw_init,
                            const std::vector<PoseObservation>& observations, const PoseStructure* structure,
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
  int64_t trace_feature = -1;  // the keyframe's feature index (link record; -1: none)
};

struct LocalBAOptions {
  int iterations_robust = 5;   // ORB-SLAM2: optimize(5) with Huber
  int iterations_refine = 10;  // ORB-SLAM2: optimize(10) without robust kernel, outliers removed
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  bool weighted_outlier_test = false;  // as PoseOnlyOptions
  void Check() const;
};

// Line and plane landmarks in local BA (issue 13): a line is its two endpoints (one 6-vector
// block, Schur-eliminated with the points), a plane its unit normal (sphere manifold) and d.
struct BALine {
  int64_t id = 0;
  Eigen::Vector3d P_s = Eigen::Vector3d::Zero(), P_e = Eigen::Vector3d::Zero();
};
struct BAPlane {
  int64_t id = 0;
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  double d = 0;
};
struct BALineObservation {
  int64_t kf_id = 0, line_id = 0;
  Eigen::Vector3d l = Eigen::Vector3d::Zero(), l_companion = Eigen::Vector3d::Zero();
  bool has_companion = false;
  double weight = 1;
  int64_t trace_line = -1;  // the keyframe's frame line index (link record; -1: none)
};
struct BAPlaneObservation {
  int64_t kf_id = 0, plane_id = 0;
  Eigen::Vector3d n_obs = Eigen::Vector3d::UnitZ();
  double d_obs = 0;
  double weight = 1;
  int64_t trace_plane = -1;  // the keyframe's frame plane index (link record; -1: none)
};
struct LocalBAStructure {
  std::vector<BALine> lines;
  std::vector<BAPlane> planes;
  std::vector<BALineObservation> line_observations;
  std::vector<BAPlaneObservation> plane_observations;
  StructureResidualOptions options;
};

struct LocalBAResult {
  std::map<int64_t, SE3> T_cw;             // every input keyframe (fixed ones unchanged)
  std::map<int64_t, Eigen::Vector3d> X_w;  // every input point
  std::vector<uint8_t> inlier;             // per input observation; 0 = outlier to erase
  std::vector<double> chi2;                // per input observation at the final estimate
  int num_inliers = 0;
  std::map<int64_t, std::pair<Eigen::Vector3d, Eigen::Vector3d>> line_P;  // every input line: P_s, P_e
  std::map<int64_t, std::pair<Eigen::Vector3d, double>> plane;           // every input plane: n, d
  std::vector<uint8_t> line_inlier, plane_inlier;                         // per structure observation
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
// The same with line and plane landmarks and observations added after the points (same phases,
// Huber delta^2 = their chi2 thresholds, outlier removal between the phases). nullptr or empty
// gives exactly the point-only call.
LocalBAResult LocalBundleAdjust(const Intrinsics& K, const std::vector<BAKeyFrame>& keyframes,
                                const std::vector<BAPoint>& points,
                                const std::vector<BAObservation>& observations, const LocalBAStructure* structure,
                                const LocalBAOptions& options, trace::TraceWriter* trace,
                                const std::string& call_id);

}  // namespace dynref::optim
