#include "optim/structure_residuals.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "optim/reprojection.h"

namespace dynref::optim {
namespace {

// Signed distance of the projection of X_c to line l and its gradient w.r.t. X_c.
bool PointLineDistance(const Intrinsics& K, const Eigen::Vector3d& X, const Eigen::Vector3d& l, double* d,
                       Eigen::RowVector3d* g) {
  const double z = X.z();
  if (!(z > kMinDepth)) return false;
  const double iz = 1.0 / z;
  const double u = K.fx * X.x() * iz + K.cx, v = K.fy * X.y() * iz + K.cy;
  *d = l.x() * u + l.y() * v + l.z();
  if (g != nullptr) *g << l.x() * K.fx * iz, l.y() * K.fy * iz, -(l.x() * K.fx * X.x() + l.y() * K.fy * X.y()) * iz * iz;
  return true;
}

}  // namespace

void StructureResidualOptions::Check() const {
  const std::string where = "structure residual options";
  if (!(line_sigma_px > 0)) throw InputError(where, "line_sigma_px must be > 0");
  if (!(plane_angle_sigma_rad > 0)) throw InputError(where, "plane angle sigma must be > 0");
  if (!(plane_dist_sigma_m > 0)) throw InputError(where, "plane_dist_sigma_m must be > 0");
  if (!(chi2_line4 > 0) || !(chi2_line1 > 0) || !(chi2_plane > 0)) throw InputError(where, "chi2 thresholds must be > 0");
}

void TangentBasis(const Eigen::Vector3d& n, Eigen::Vector3d* b1, Eigen::Vector3d* b2) {
  // The coordinate axis least aligned with n seeds the basis.
  const Eigen::Vector3d a = std::fabs(n.x()) <= std::fabs(n.y()) && std::fabs(n.x()) <= std::fabs(n.z())
                                ? Eigen::Vector3d::UnitX()
                                : std::fabs(n.y()) <= std::fabs(n.z()) ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  *b1 = n.cross(a).normalized();
  *b2 = n.cross(*b1);
}

bool LineResidualRaw(const Intrinsics& K, const std::array<Eigen::Vector3d, 3>& X_c, const Eigen::Vector3d& l,
                     const Eigen::Vector3d* l_companion, bool literal, double* r, Eigen::Matrix<double, 4, 9>* dr_dX) {
  double d[3], dc[3] = {0, 0, 0};
  Eigen::RowVector3d g[3], gc[3];
  for (int k = 0; k < 3; ++k) {
    if (!PointLineDistance(K, X_c[static_cast<size_t>(k)], l, &d[k], &g[k])) return false;
    gc[k].setZero();
    if (l_companion != nullptr) PointLineDistance(K, X_c[static_cast<size_t>(k)], *l_companion, &dc[k], &gc[k]);
  }
  // e_col + e_par and its gradient blocks (s: +1, m: -2, e: +1).
  const double e = (d[0] + d[2] - 2 * d[1]) + (dc[0] + dc[2] - 2 * dc[1]);
  const Eigen::RowVector3d ge[3] = {g[0] + gc[0], -2 * (g[1] + gc[1]), g[2] + gc[2]};
  if (literal) {
    r[0] = e;
    if (dr_dX != nullptr) {
      dr_dX->setZero();
      for (int k = 0; k < 3; ++k) dr_dX->block<1, 3>(0, 3 * k) = ge[k];
    }
    return true;
  }
  r[0] = d[0], r[1] = d[1], r[2] = d[2], r[3] = e;
  if (dr_dX != nullptr) {
    dr_dX->setZero();
    for (int k = 0; k < 3; ++k) {
      dr_dX->block<1, 3>(k, 3 * k) = g[k];
      dr_dX->block<1, 3>(3, 3 * k) = ge[k];
    }
  }
  return true;
}

bool PlaneResidualRaw(const Eigen::Vector3d& n_c, double d_c, const Eigen::Vector3d& n_obs, double d_obs, double* r) {
  if (!(n_c.dot(n_obs) > 0)) return false;  // facing away: not the same plane side
  Eigen::Vector3d b1, b2;
  TangentBasis(n_obs, &b1, &b2);
  r[0] = b1.dot(n_c), r[1] = b2.dot(n_c), r[2] = d_c - d_obs;
  return true;
}

// ---- pose-only ----

LinePoseCost::LinePoseCost(const Intrinsics& K, const LineObservation& o, const StructureResidualOptions& opt)
    : K_(K), o_(o), literal_(opt.literal_line), s_(std::sqrt(o.weight) / opt.line_sigma_px) {
  set_num_residuals(opt.LineDim());
  mutable_parameter_block_sizes()->push_back(7);
}

bool LinePoseCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  std::array<Eigen::Vector3d, 3> X_c;
  for (size_t k = 0; k < 3; ++k) X_c[k] = q * o_.X_w[k] + t;
  const int dim = literal_ ? 1 : 4;
  double r[4];
  Eigen::Matrix<double, 4, 9> dr;
  const bool want = jacobians != nullptr && jacobians[0] != nullptr;
  if (!LineResidualRaw(K_, X_c, o_.l, o_.has_companion ? &o_.l_companion : nullptr, literal_, r, want ? &dr : nullptr))
    return false;
  for (int i = 0; i < dim; ++i) residuals[i] = s_ * r[i];
  if (want) {
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 7, Eigen::RowMajor>> J(jacobians[0], dim, 7);
    J.setZero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Matrix<double, 4, 3> Dk = s_ * dr.block<4, 3>(0, 3 * k);
      J.leftCols<3>() += Dk.topRows(dim) * (-Skew(X_c[static_cast<size_t>(k)]));
      J.middleCols<3>(3) += Dk.topRows(dim);
    }
  }
  return true;
}

PlanePoseCost::PlanePoseCost(const PlaneObservationResidual& o, const StructureResidualOptions& opt)
    : o_(o),
      sa_(std::sqrt(o.weight) / opt.plane_angle_sigma_rad),
      sd_(std::sqrt(o.weight) / opt.plane_dist_sigma_m) {
  TangentBasis(o.n_obs, &b1_, &b2_);
}

bool PlanePoseCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Vector3d n_c = q * o_.n_w;
  const double d_c = o_.d_w - n_c.dot(t);
  double r[3];
  if (!PlaneResidualRaw(n_c, d_c, o_.n_obs, o_.d_obs, r)) return false;
  residuals[0] = sa_ * r[0], residuals[1] = sa_ * r[1], residuals[2] = sd_ * r[2];
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    const Eigen::Matrix3d dn = -Skew(n_c);  // d n_c / d omega
    J.block<1, 3>(0, 0) = sa_ * b1_.transpose() * dn;
    J.block<1, 3>(1, 0) = sa_ * b2_.transpose() * dn;
    J.block<1, 3>(2, 3) = -sd_ * n_c.transpose();
  }
  return true;
}

// ---- local BA ----

LineBACost::LineBACost(const Intrinsics& K, const Eigen::Vector3d& l, const Eigen::Vector3d* l_companion,
                       double weight, const StructureResidualOptions& opt)
    : K_(K),
      l_(l),
      lc_(l_companion != nullptr ? *l_companion : Eigen::Vector3d::Zero()),
      has_c_(l_companion != nullptr),
      literal_(opt.literal_line),
      s_(std::sqrt(weight) / opt.line_sigma_px) {
  set_num_residuals(opt.LineDim());
  mutable_parameter_block_sizes()->push_back(7);
  mutable_parameter_block_sizes()->push_back(6);
}

bool LineBACost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Map<const Eigen::Vector3d> Ps(parameters[1]), Pe(parameters[1] + 3);
  const std::array<Eigen::Vector3d, 3> X_w = {Eigen::Vector3d(Ps), Eigen::Vector3d(0.5 * (Ps + Pe)), Eigen::Vector3d(Pe)};
  std::array<Eigen::Vector3d, 3> X_c;
  for (size_t k = 0; k < 3; ++k) X_c[k] = q * X_w[k] + t;
  const int dim = literal_ ? 1 : 4;
  double r[4];
  Eigen::Matrix<double, 4, 9> dr;
  const bool want = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
  if (!LineResidualRaw(K_, X_c, l_, has_c_ ? &lc_ : nullptr, literal_, r, want ? &dr : nullptr)) return false;
  for (int i = 0; i < dim; ++i) residuals[i] = s_ * r[i];
  if (!want) return true;
  dr *= s_;
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 7, Eigen::RowMajor>> J(jacobians[0], dim, 7);
    J.setZero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Matrix<double, 4, 3> Dk = dr.block<4, 3>(0, 3 * k);
      J.leftCols<3>() += Dk.topRows(dim) * (-Skew(X_c[static_cast<size_t>(k)]));
      J.middleCols<3>(3) += Dk.topRows(dim);
    }
  }
  if (jacobians[1] != nullptr) {
    const Eigen::Matrix3d R = q.toRotationMatrix();
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>> J(jacobians[1], dim, 6);
    const Eigen::Matrix<double, 4, 3> Js = (dr.block<4, 3>(0, 0) + 0.5 * dr.block<4, 3>(0, 3)) * R;
    const Eigen::Matrix<double, 4, 3> Je = (0.5 * dr.block<4, 3>(0, 3) + dr.block<4, 3>(0, 6)) * R;
    J.leftCols<3>() = Js.topRows(dim);
    J.rightCols<3>() = Je.topRows(dim);
  }
  return true;
}

PlaneBACost::PlaneBACost(const Eigen::Vector3d& n_obs, double d_obs, double weight, const StructureResidualOptions& opt)
    : n_obs_(n_obs),
      d_obs_(d_obs),
      sa_(std::sqrt(weight) / opt.plane_angle_sigma_rad),
      sd_(std::sqrt(weight) / opt.plane_dist_sigma_m) {
  TangentBasis(n_obs, &b1_, &b2_);
}

bool PlaneBACost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Map<const Eigen::Vector3d> n_w(parameters[1]);
  const double d_w = parameters[2][0];
  const Eigen::Vector3d n_c = q * n_w;
  const double d_c = d_w - n_c.dot(t);
  double r[3];
  if (!PlaneResidualRaw(n_c, d_c, n_obs_, d_obs_, r)) return false;
  residuals[0] = sa_ * r[0], residuals[1] = sa_ * r[1], residuals[2] = sd_ * r[2];
  if (jacobians == nullptr) return true;
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    const Eigen::Matrix3d dn = -Skew(n_c);
    J.block<1, 3>(0, 0) = sa_ * b1_.transpose() * dn;
    J.block<1, 3>(1, 0) = sa_ * b2_.transpose() * dn;
    J.block<1, 3>(2, 3) = -sd_ * n_c.transpose();
  }
  if (jacobians[1] != nullptr) {
    const Eigen::Matrix3d R = q.toRotationMatrix();
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobians[1]);
    J.row(0) = sa_ * b1_.transpose() * R;
    J.row(1) = sa_ * b2_.transpose() * R;
    J.row(2) = -sd_ * t.transpose() * R;
  }
  if (jacobians[2] != nullptr) {
    jacobians[2][0] = 0, jacobians[2][1] = 0, jacobians[2][2] = sd_;
  }
  return true;
}

LineGaugePrior::LineGaugePrior(const Eigen::Vector3d& P_s0, const Eigen::Vector3d& P_e0, double sigma_m)
    : P_s0_(P_s0), P_e0_(P_e0), u0_((P_e0 - P_s0).normalized()), inv_sigma_(1.0 / sigma_m) {}

bool LineGaugePrior::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> Ps(parameters[0]), Pe(parameters[0] + 3);
  residuals[0] = inv_sigma_ * (Ps - P_s0_).dot(u0_);
  residuals[1] = inv_sigma_ * (Pe - P_e0_).dot(u0_);
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J.block<1, 3>(0, 0) = inv_sigma_ * u0_.transpose();
    J.block<1, 3>(1, 3) = inv_sigma_ * u0_.transpose();
  }
  return true;
}

double LineChi2(const Intrinsics& K, const SE3& T_cw, const LineObservation& o, const StructureResidualOptions& opt,
                std::vector<double>* raw, double* weighted_chi2) {
  std::array<Eigen::Vector3d, 3> X_c;
  for (size_t k = 0; k < 3; ++k) X_c[k] = T_cw * o.X_w[k];
  double r[4];
  const int dim = opt.LineDim();
  if (!LineResidualRaw(K, X_c, o.l, o.has_companion ? &o.l_companion : nullptr, opt.literal_line, r, nullptr)) {
    if (raw != nullptr) raw->clear();
    if (weighted_chi2 != nullptr) *weighted_chi2 = std::numeric_limits<double>::infinity();
    return std::numeric_limits<double>::infinity();
  }
  if (raw != nullptr) raw->assign(r, r + dim);
  double sq = 0;
  for (int i = 0; i < dim; ++i) sq += r[i] * r[i];
  const double c = sq / (opt.line_sigma_px * opt.line_sigma_px);
  if (weighted_chi2 != nullptr) *weighted_chi2 = o.weight * c;
  return c;
}

double PlaneChi2(const SE3& T_cw, const PlaneObservationResidual& o, const StructureResidualOptions& opt,
                 std::vector<double>* raw, double* weighted_chi2) {
  const Eigen::Vector3d n_c = T_cw.linear() * o.n_w;
  const double d_c = o.d_w - n_c.dot(T_cw.translation());
  double r[3];
  if (!PlaneResidualRaw(n_c, d_c, o.n_obs, o.d_obs, r)) {
    if (raw != nullptr) raw->clear();
    if (weighted_chi2 != nullptr) *weighted_chi2 = std::numeric_limits<double>::infinity();
    return std::numeric_limits<double>::infinity();
  }
  if (raw != nullptr) raw->assign(r, r + 3);
  const double a2 = opt.plane_angle_sigma_rad * opt.plane_angle_sigma_rad;
  const double c = (r[0] * r[0] + r[1] * r[1]) / a2 + r[2] * r[2] / (opt.plane_dist_sigma_m * opt.plane_dist_sigma_m);
  if (weighted_chi2 != nullptr) *weighted_chi2 = o.weight * c;
  return c;
}

}  // namespace dynref::optim
