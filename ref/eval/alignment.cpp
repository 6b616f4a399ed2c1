#include "eval/alignment.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <stdexcept>
#include <string>

namespace dynref {

const char* AlignModeName(AlignMode mode) {
  switch (mode) {
    case AlignMode::kSE3: return "se3";
    case AlignMode::kSim3: return "sim3";
    case AlignMode::kNone: return "none";
  }
  return "?";
}

Similarity3 AlignPoints(const std::vector<Eigen::Vector3d>& est,
                        const std::vector<Eigen::Vector3d>& gt, AlignMode mode) {
  if (est.size() != gt.size()) throw std::invalid_argument("AlignPoints: size mismatch");
  Similarity3 S;
  if (mode == AlignMode::kNone) return S;
  if (est.size() < 3) throw std::invalid_argument("AlignPoints: needs at least 3 pairs");
  const double n = static_cast<double>(est.size());
  Eigen::Vector3d mu_est = Eigen::Vector3d::Zero(), mu_gt = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < est.size(); ++i) {
    mu_est += est[i];
    mu_gt += gt[i];
  }
  mu_est /= n;
  mu_gt /= n;
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
  double var_est = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    const Eigen::Vector3d e = est[i] - mu_est;
    sigma += (gt[i] - mu_gt) * e.transpose();
    var_est += e.squaredNorm();
  }
  sigma /= n;
  var_est /= n;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  Eigen::Matrix3d W = Eigen::Matrix3d::Identity();
  if (U.determinant() * V.determinant() < 0) W(2, 2) = -1;  // reflection guard (Eq. 39)
  S.R = U * W * V.transpose();
  if (mode == AlignMode::kSim3) {
    if (!(var_est > 0))
      throw std::invalid_argument("--align sim3: all " + std::to_string(est.size()) +
                                  " associated estimate positions coincide, so no scale can be estimated "
                                  "(use --align se3 or none)");
    S.scale = (svd.singularValues().asDiagonal() * W).trace() / var_est;  // Eq. (42)
  }
  S.t = mu_gt - S.scale * (S.R * mu_est);
  return S;
}

}  // namespace dynref
