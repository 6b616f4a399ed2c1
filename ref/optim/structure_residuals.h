// Line and plane residuals of seed 000 (Sec. 3.6, spec 000 step 14, E15-E17; issue 13), as
// Ceres cost functors with analytic Jacobians (tests/optim/structure_residuals_test.cpp checks
// each against central differences through the manifolds).
//
// LINE. Observation: the normalised image line l of a frame segment (l . (u, v, 1) = signed
// pixel distance) and, when its parallel group has one, the companion line l'. Landmark: the
// samples X_s, X_m, X_e (world). With pi() the pinhole projection of X_c = R X_w + t:
//   d_x  = l^T  [pi(X_c,x); 1]           x in {s, m, e}     point-to-line distances (px)
//   e_col = d_s + d_e - 2 d_m                                collinearity (spec step 14)
//   e_par = d'_s + d'_e - 2 d'_m  with l'                    parallel term (0 without companion)
// Vector form (default, spec E15 proposed): r = [d_s, d_m, d_e, e_col + e_par]  (4 dof)
// Literal form (config switch):                r = [e_col + e_par]               (1 dof)
// d d_x / d X_c = [l1 fx / z,  l2 fy / z,  -(l1 fx x + l2 fy y) / z^2].
// In local BA the landmark is one 6-vector [P_s; P_e] (X_m = (P_s + P_e) / 2), so that it is a
// single Schur-eliminated block.
//
// PLANE. Observation (n_o, d_o) in the camera; landmark (n_w, d_w) in the world. In the camera:
//   n_c = R n_w,   d_c = d_w - n_c^T t          (from n_w^T X_w + d_w = 0, X_w = R^T (X_c - t))
// r = [ b1^T n_c / sigma_a,  b2^T n_c / sigma_a,  (d_c - d_o) / sigma_d ]        (3 dof)
// with (b1, b2) an orthonormal basis of the plane orthogonal to n_o: for a small angle the first
// two components are the angle between n_c and n_o resolved on two axes (the spec's
// "angle(R n_w, n_obs)" as a smooth 2-vector; E16: coplanarity only, T_cw form).
// Left-perturbation Jacobians (omega, upsilon): d n_c / d omega = -[n_c]x, d d_c / d omega = 0,
// d d_c / d upsilon = -n_c^T. Landmark: d n_c / d n_w = R, d d_c / d n_w = -t^T R, d d_c / d d_w = 1;
// n_w lives on ceres::SphereManifold<3>.
//
// Whitening: every residual is multiplied by sqrt(weight) (a method's per-observation weight,
// as for points), lines additionally by 1 / sigma_l.
#pragma once
#include <ceres/ceres.h>

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "optim/optim.h"

namespace dynref::optim {

// Raw (unwhitened) line residual of camera-frame samples; false when a sample is not in front.
bool LineResidualRaw(const Intrinsics& K, const std::array<Eigen::Vector3d, 3>& X_c, const Eigen::Vector3d& l,
                     const Eigen::Vector3d* l_companion, bool literal, double* r,
                     Eigen::Matrix<double, 4, 9>* dr_dX);  // columns: X_s, X_m, X_e
// Raw plane residual components [b1.n_c, b2.n_c, d_c - d_o]; false when n_c faces away from n_o.
bool PlaneResidualRaw(const Eigen::Vector3d& n_c, double d_c, const Eigen::Vector3d& n_obs, double d_obs, double* r);
// Orthonormal basis of the plane orthogonal to unit n (deterministic).
void TangentBasis(const Eigen::Vector3d& n, Eigen::Vector3d* b1, Eigen::Vector3d* b2);

// Pose-only functors (parameter: pose, 7).
class LinePoseCost final : public ceres::CostFunction {
 public:
  LinePoseCost(const Intrinsics& K, const LineObservation& o, const StructureResidualOptions& opt);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
 private:
  Intrinsics K_;
  LineObservation o_;
  bool literal_;
  double s_;
};
class PlanePoseCost final : public ceres::SizedCostFunction<3, 7> {
 public:
  PlanePoseCost(const PlaneObservationResidual& o, const StructureResidualOptions& opt);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
 private:
  PlaneObservationResidual o_;
  Eigen::Vector3d b1_, b2_;
  double sa_, sd_;
};

// Local-BA functors (parameters: pose 7, line [P_s; P_e] 6) and (pose 7, n_w 3, d_w 1).
class LineBACost final : public ceres::CostFunction {
 public:
  LineBACost(const Intrinsics& K, const Eigen::Vector3d& l, const Eigen::Vector3d* l_companion, double weight,
             const StructureResidualOptions& opt);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
 private:
  Intrinsics K_;
  Eigen::Vector3d l_, lc_;
  bool has_c_, literal_;
  double s_;
};
class PlaneBACost final : public ceres::SizedCostFunction<3, 7, 3, 1> {
 public:
  PlaneBACost(const Eigen::Vector3d& n_obs, double d_obs, double weight, const StructureResidualOptions& opt);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
 private:
  Eigen::Vector3d n_obs_, b1_, b2_;
  double d_obs_, sa_, sd_;
};

// Gauge prior of a line in local BA: sliding an endpoint along the line changes no image residual
// (a null space that lets LM move endpoints metres away), so each endpoint is tied along the
// initial direction u0: r = [(P_s - P_s0) . u0, (P_e - P_e0) . u0] / sigma. Orthogonal motion is
// free: the prior biases nothing the images constrain. Linear, constant Jacobian.
class LineGaugePrior final : public ceres::SizedCostFunction<2, 6> {
 public:
  LineGaugePrior(const Eigen::Vector3d& P_s0, const Eigen::Vector3d& P_e0, double sigma_m);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
 private:
  Eigen::Vector3d P_s0_, P_e0_, u0_;
  double inv_sigma_;
};

// Unwhitened residual and chi2 (whitened, weight 1 = the outlier test) of a line / plane
// observation at a pose; chi2 = +inf when not evaluable.
double LineChi2(const Intrinsics& K, const SE3& T_cw, const LineObservation& o, const StructureResidualOptions& opt,
                std::vector<double>* raw, double* weighted_chi2);
double PlaneChi2(const SE3& T_cw, const PlaneObservationResidual& o, const StructureResidualOptions& opt,
                 std::vector<double>* raw, double* weighted_chi2);

}  // namespace dynref::optim
