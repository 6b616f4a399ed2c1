// Least-squares alignment of corresponding 3-D points (estimate -> ground truth):
// Umeyama (IEEE PAMI 1991) = Horn (JOSA A 1987) closed form via SVD, as in TUM's
// evaluate_ate.py `align()` (no scale) and evo's `umeyama_alignment` (with or without scale).
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace dynref {

enum class AlignMode { kSE3, kSim3, kNone };
const char* AlignModeName(AlignMode mode);  // "se3" / "sim3" / "none"

struct Similarity3 {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double scale = 1.0;
  Eigen::Vector3d Apply(const Eigen::Vector3d& p) const { return scale * (R * p) + t; }
};

// Finds S minimising sum |gt_i - S(est_i)|^2 (kNone: identity). Umeyama 1991 Eqs. (38)-(42):
// Sigma = 1/n sum (gt_i - mu_gt)(est_i - mu_est)^T = U D V^T, W = diag(1, 1, det(U)det(V) < 0 ?
// -1 : 1), R = U W V^T, c = tr(D W) / sigma_est^2, t = mu_gt - c R mu_est.
// Requires est.size() == gt.size() >= 3 for kSE3/kSim3 (std::invalid_argument otherwise).
Similarity3 AlignPoints(const std::vector<Eigen::Vector3d>& est,
                        const std::vector<Eigen::Vector3d>& gt, AlignMode mode);

}  // namespace dynref
