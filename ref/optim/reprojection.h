// Ceres building blocks of the optimisation room: the SE3 pose manifold and the reprojection
// cost functors (ORB-SLAM2 / g2o EdgeSE3ProjectXYZ(OnlyPose) and
// EdgeStereoSE3ProjectXYZ(OnlyPose)).
#pragma once
#include <ceres/ceres.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "core/se3.h"
#include "optim/optim.h"

namespace dynref::optim {

// ---------------------------------------------------------------------------------------------
// Pose parameter block (ambient size 7): [qx qy qz qw tx ty tz] of T_cw (Eigen coeff order),
// the quaternion kept unit length.
// Tangent (size 6): delta = (omega, upsilon), applied on the left as in g2o's VertexSE3Expmap:
//   Plus(T, delta) = Exp(delta) * T,  Exp(omega, upsilon) = [Exp_SO3(omega), V(omega) upsilon].
//
// Jacobian convention (derived, not Ceres' quaternion chain rule): the cost functors below write
// their "ambient" pose Jacobian as [d e / d delta | 0] (N x 7, last column zero), and
// PlusJacobian(T) = [I_6; 0] (7 x 6). Ceres only ever uses the product
//   J_ambient * PlusJacobian = d e(Exp(delta) T) / d delta |_{delta=0},
// which is therefore the exact tangent-space Jacobian (tests/optim check it numerically through
// Plus). MinusJacobian = [I_6 0] so that MinusJacobian * PlusJacobian = I_6.
// ---------------------------------------------------------------------------------------------
class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// [w]x, the cross-product matrix (Skew(w) v = w x v).
inline Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return W;
}

void PoseToParams(const SE3& T_cw, double* params7);
SE3 ParamsToPose(const double* params7);
// SE3 exponential / logarithm in the (omega, upsilon) ordering above.
SE3 ExpSE3(const Eigen::Matrix<double, 6, 1>& delta);
Eigen::Matrix<double, 6, 1> LogSE3(const SE3& T);

// ---------------------------------------------------------------------------------------------
// Projection residual shared by all functors (N = 3: RGB-D "stereo", N = 2: monocular).
//   X_c = R X_w + t = (x, y, z),  pi(X_c) = (fx x/z + cx,  fy y/z + cy,  fx x/z + cx - bf/z)
//   e = s * (obs - pi(X_c)),  s = sqrt(inv_sigma2 * weight)   (whitening: e^T e = chi2)
//   d pi / d X_c = [ fx/z   0     -fx x/z^2        ]
//                  [ 0      fy/z  -fy y/z^2        ]
//                  [ fx/z   0     -fx x/z^2 + bf/z^2 ]   (third row only for N = 3)
//   d e / d X_c = -s * d pi / d X_c
// Returns false when z <= kMinDepth (point not in front of the camera): Ceres then rejects the
// step; classification treats such observations as outliers.
// ---------------------------------------------------------------------------------------------
constexpr double kMinDepth = 1e-9;

template <int N>
inline bool ProjectionResidual(const Intrinsics& K, const Eigen::Vector3d& X_c,
                               const Eigen::Vector3d& obs, double s, double* e,
                               Eigen::Matrix<double, N, 3>* de_dXc) {
  static_assert(N == 2 || N == 3, "residual is 2- or 3-dof");
  const double z = X_c.z();
  if (!(z > kMinDepth)) return false;
  const double inv_z = 1.0 / z;
  const double u = K.fx * X_c.x() * inv_z + K.cx;
  const double v = K.fy * X_c.y() * inv_z + K.cy;
  e[0] = s * (obs[0] - u);
  e[1] = s * (obs[1] - v);
  if constexpr (N == 3) e[2] = s * (obs[2] - (u - K.bf * inv_z));
  if (de_dXc != nullptr) {
    const double inv_z2 = inv_z * inv_z;
    auto& J = *de_dXc;
    J(0, 0) = -s * K.fx * inv_z;
    J(0, 1) = 0.0;
    J(0, 2) = s * K.fx * X_c.x() * inv_z2;
    J(1, 0) = 0.0;
    J(1, 1) = -s * K.fy * inv_z;
    J(1, 2) = s * K.fy * X_c.y() * inv_z2;
    if constexpr (N == 3) {
      J(2, 0) = -s * K.fx * inv_z;
      J(2, 1) = 0.0;
      J(2, 2) = s * (K.fx * X_c.x() * inv_z2 - K.bf * inv_z2);
    }
  }
  return true;
}

// Pose-only cost (ORB-SLAM2 EdgeSE3ProjectXYZOnlyPose / EdgeStereoSE3ProjectXYZOnlyPose):
// parameter = pose block (7). With X_c = Exp(delta) T X_w ~ X_c + omega x X_c + upsilon,
//   d X_c / d delta = [ -[X_c]_x | I_3 ]
//   d e / d delta   = d e / d X_c * [ -[X_c]_x | I_3 ]
template <int N>
class PoseOnlyCost final : public ceres::SizedCostFunction<N, 7> {
 public:
  PoseOnlyCost(const Intrinsics& K, const Eigen::Vector3d& X_w, const Eigen::Vector3d& obs,
               double sqrt_info)
      : K_(K), X_w_(X_w), obs_(obs), s_(sqrt_info) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Intrinsics K_;
  Eigen::Vector3d X_w_;
  Eigen::Vector3d obs_;  // (u, v, u_right); u_right unused for N = 2
  double s_;
};

// Local-BA cost (ORB-SLAM2 EdgeSE3ProjectXYZ / EdgeStereoSE3ProjectXYZ):
// parameters = pose block (7), point block X_w (3).
//   d e / d delta = d e / d X_c * [ -[X_c]_x | I_3 ]   (as above)
//   d e / d X_w   = d e / d X_c * R
template <int N>
class BACost final : public ceres::SizedCostFunction<N, 7, 3> {
 public:
  BACost(const Intrinsics& K, const Eigen::Vector3d& obs, double sqrt_info)
      : K_(K), obs_(obs), s_(sqrt_info) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Intrinsics K_;
  Eigen::Vector3d obs_;
  double s_;
};

// Raw (unwhitened) residual obs - pi(T_cw X_w) into e (size N); false if z <= kMinDepth.
template <int N>
bool RawResidual(const Intrinsics& K, const SE3& T_cw, const Eigen::Vector3d& X_w,
                 const Eigen::Vector3d& obs, double* e);

// g2o RobustKernelHuber on a squared error s with delta^2 = delta2.
double HuberRho(double s, double delta2);

// Per-observation constants shared by pose-only optimisation and local BA (optim.h conventions).
struct EdgeModel {
  bool stereo = false;                            // rgbd3 (u_right >= 0) or mono2
  Eigen::Vector3d obs = Eigen::Vector3d::Zero();  // (u, v, u_right)
  double info = 0;                                // inv_sigma2 * weight (the optimised cost)
  double test_info = 0;                           // information of the outlier test (see below)
  double threshold = 0;                           // chi2 threshold of this residual kind
};
// weighted_test = false (default of both calls, issue 21): the outlier test uses the keypoint's
// own information inv_sigma2, so a down-weighted dynamic observation with a large error is still
// an outlier (ORB-SLAM2 has no weights; the weight is SGDO's omega / MGD's 1 - P, which must only
// scale the residual's influence). true: the test uses inv_sigma2 * weight (dynref <= v0.1).
EdgeModel MakeEdgeModel(const Eigen::Vector2d& uv, double u_right, double inv_sigma2, double weight,
                        double chi2_mono, double chi2_stereo, bool weighted_test);

// Outlier-test chi2 = test_info * |obs - pi(T_cw X_w)|^2 of one edge; +inf (outlier) when the
// point is not in front of the camera. The optimised chi2 (info * |.|^2) goes to *weighted_chi2
// and the raw (unwhitened) residual to *raw when given (empty when invalid).
double EdgeChi2(const Intrinsics& K, const SE3& T_cw, const Eigen::Vector3d& X_w,
                const EdgeModel& edge, std::vector<double>* raw, double* weighted_chi2 = nullptr);

// Link record of one residual (optim.h "Link records"): PROB of stage LinkStage(call_id) on the
// observation id, p = 0; written only when `index` >= 0 (the caller named the frame item).
std::string LinkStage(const std::string& call_id);  // "track.pose#2" -> "track.pose.obs"
void WriteResidualLink(trace::TraceWriter& trace, const std::string& link_stage, int kind,
                       const std::string& obs_id, const char* index_name, int64_t index,
                       std::initializer_list<std::pair<const char*, double>> more);

extern template class PoseOnlyCost<2>;
extern template class PoseOnlyCost<3>;
extern template class BACost<2>;
extern template class BACost<3>;

}  // namespace dynref::optim
