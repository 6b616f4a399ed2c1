// seed 001, Sec. 3.3: fundamental matrix by RANSAC with the 7-point solver, and the point to
// epipolar-line distance of Eq. (5). Own implementation so that every random draw comes from
// dynref::Rng(seed, "sgdo.F") (CONTRIBUTING: no cv::RNG); Eigen only for linear algebra.
// Convention: x_cur^T F x_prev = 0 (P1 = previous frame, P2 = current frame, as in the paper).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/rng.h"

namespace dynref::geometry {

struct Correspondence {
  Eigen::Vector2d p_prev;  // P1
  Eigen::Vector2d p_cur;   // P2
};

// Eq. (5): L2 = F P1h = (X, Y, Z)^T, D = |P2h^T F P1h| / sqrt(X^2 + Y^2). +inf if X = Y = 0.
double EpipolarDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& p_prev,
                        const Eigen::Vector2d& p_cur);
// max(distance of P2 to F P1, distance of P1 to F^T P2): the RANSAC inlier error (as OpenCV's
// FM estimator), symmetric so that a wrong F cannot hide errors in one image.
double SymmetricEpipolarDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& p_prev,
                                 const Eigen::Vector2d& p_cur);

// F of a calibrated relative pose (seed 000 Sec. 3.5, seed 004 Module C): F = K^-T [t]x R K^-1
// with (R, t) = T_cur_prev (maps points of the previous camera into the current one), so that
// x_cur^T F x_prev = 0. K = [fx 0 cx; 0 fy cy; 0 0 1].
Eigen::Matrix3d FundamentalFromPose(const Eigen::Matrix3d& K, const Eigen::Matrix3d& R_cur_prev,
                                    const Eigen::Vector3d& t_cur_prev);

// Minimal solver: the 1..3 real rank-2 solutions of exactly 7 correspondences (Hartley &
// Zisserman Sec. 11.1.2: null space {F1, F2}, cubic det(a F1 + (1-a) F2) = 0). Points are
// Hartley-normalised internally. Each F is scaled to unit Frobenius norm with F(2,2) >= 0
// (or the first non-zero entry positive).
std::vector<Eigen::Matrix3d> SevenPointSolve(const std::vector<Correspondence>& seven);

// Linear 8-point least squares on >= 8 correspondences with rank-2 enforcement (normalised).
// Returns false if fewer than 8 points or the system is degenerate.
bool EightPointFit(const std::vector<Correspondence>& points, Eigen::Matrix3d& F);

struct RansacOptions {
  double inlier_threshold_px = 1.0;  // not stated (spec 001 (c)): 1.0 px
  double confidence = 0.99;          // not stated: 0.99
  int max_iterations = 1000;         // not stated: OpenCV's findFundamentalMat default cap
  int min_points = 8;                // below this no F is estimated (7 + 1 check point)
  bool final_refit = true;           // 8-point refit on all inliers, kept if not worse
  void Check() const;
};

struct RansacResult {
  bool valid = false;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  std::vector<uint8_t> inliers;  // per input correspondence
  int inlier_count = 0;
  int iterations = 0;
  bool refit_used = false;
};

// Draws 7 distinct indices per iteration from `rng`; adaptive stopping
// N = log(1 - confidence) / log(1 - w^7) with w the best inlier ratio so far. Score = inlier
// count; ties keep the earlier model. Deterministic for a given rng state.
RansacResult RansacFundamental(const std::vector<Correspondence>& points,
                               const RansacOptions& options, Rng& rng);

}  // namespace dynref::geometry
