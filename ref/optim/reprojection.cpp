#include "optim/reprojection.h"

#include <cmath>
#include <limits>

#include "trace/trace_writer.h"

namespace dynref::optim {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Exp_SO3 as a unit quaternion (first-order series below 1e-10 rad).
Eigen::Quaterniond ExpSO3(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  if (theta < 1e-10) {
    return Eigen::Quaterniond(1.0, 0.5 * omega.x(), 0.5 * omega.y(), 0.5 * omega.z()).normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta, omega / theta));
}

// Left Jacobian of SO3, V(omega) = I + (1 - cos t)/t^2 W + (t - sin t)/t^3 W^2 (Barfoot, State
// Estimation for Robotics, Eq. 7.86); its Taylor series near 0.
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  const Eigen::Matrix3d W = Skew(omega);
  if (theta < 1e-5) return Eigen::Matrix3d::Identity() + 0.5 * W + (1.0 / 6.0) * W * W;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + ((1.0 - std::cos(theta)) / t2) * W +
         ((theta - std::sin(theta)) / (t2 * theta)) * W * W;
}

// V(omega)^-1 = I - W/2 + (1/t^2) (1 - t sin t / (2 (1 - cos t))) W^2.
Eigen::Matrix3d InverseLeftJacobianSO3(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  const Eigen::Matrix3d W = Skew(omega);
  if (theta < 1e-5) return Eigen::Matrix3d::Identity() - 0.5 * W + (1.0 / 12.0) * W * W;
  const double t2 = theta * theta;
  const double c = (1.0 - theta * std::sin(theta) / (2.0 * (1.0 - std::cos(theta)))) / t2;
  return Eigen::Matrix3d::Identity() - 0.5 * W + c * W * W;
}

}  // namespace

SE3 ExpSE3(const Vector6d& delta) {
  const Eigen::Vector3d omega = delta.head<3>();
  SE3 T = SE3::Identity();
  T.linear() = ExpSO3(omega).toRotationMatrix();
  T.translation() = LeftJacobianSO3(omega) * delta.tail<3>();
  return T;
}

Vector6d LogSE3(const SE3& T) {
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(T.linear()).normalized());
  const Eigen::Vector3d omega = aa.angle() * aa.axis();
  Vector6d delta;
  delta.head<3>() = omega;
  delta.tail<3>() = InverseLeftJacobianSO3(omega) * T.translation();
  return delta;
}

void PoseToParams(const SE3& T_cw, double* params7) {
  const Eigen::Quaterniond q = Eigen::Quaterniond(T_cw.linear()).normalized();
  params7[0] = q.x();
  params7[1] = q.y();
  params7[2] = q.z();
  params7[3] = q.w();
  params7[4] = T_cw.translation().x();
  params7[5] = T_cw.translation().y();
  params7[6] = T_cw.translation().z();
}

SE3 ParamsToPose(const double* params7) {
  const Eigen::Quaterniond q(params7[3], params7[0], params7[1], params7[2]);
  return MakeSE3(Eigen::Vector3d(params7[4], params7[5], params7[6]), q);
}

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Quaterniond> q(x);
  const Eigen::Map<const Eigen::Vector3d> t(x + 4);
  const Eigen::Map<const Vector6d> d(delta);
  const Eigen::Vector3d omega = d.head<3>();
  const Eigen::Quaterniond dq = ExpSO3(omega);
  // Exp(delta) * T = [dR R, dR t + V(omega) upsilon]
  const Eigen::Quaterniond q_new = (dq * q).normalized();
  const Eigen::Vector3d t_new = dq * t + LeftJacobianSO3(omega) * d.tail<3>();
  Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta);
  Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta + 4);
  q_out = q_new;
  t_out = t_new;
  return true;
}

bool PoseManifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topRows<6>().setIdentity();
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const SE3 Y = ParamsToPose(y);
  const SE3 X = ParamsToPose(x);
  Eigen::Map<Vector6d> out(y_minus_x);
  out = LogSE3(Y * X.inverse());
  return true;
}

bool PoseManifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.leftCols<6>().setIdentity();
  return true;
}

template <int N>
bool PoseOnlyCost<N>::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Vector3d X_c = q * X_w_ + t;
  if (jacobians == nullptr || jacobians[0] == nullptr) {
    return ProjectionResidual<N>(K_, X_c, obs_, s_, residuals, nullptr);
  }
  Eigen::Matrix<double, N, 3> de_dXc;
  if (!ProjectionResidual<N>(K_, X_c, obs_, s_, residuals, &de_dXc)) return false;
  Eigen::Map<Eigen::Matrix<double, N, 7, Eigen::RowMajor>> J(jacobians[0]);
  J.template leftCols<3>() = -de_dXc * Skew(X_c);
  J.template middleCols<3>(3) = de_dXc;
  J.col(6).setZero();
  return true;
}

template <int N>
bool BACost<N>::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Map<const Eigen::Vector3d> X_w(parameters[1]);
  const Eigen::Vector3d X_c = q * X_w + t;
  const bool want_pose = jacobians != nullptr && jacobians[0] != nullptr;
  const bool want_point = jacobians != nullptr && jacobians[1] != nullptr;
  if (!want_pose && !want_point)
    return ProjectionResidual<N>(K_, X_c, obs_, s_, residuals, nullptr);
  Eigen::Matrix<double, N, 3> de_dXc;
  if (!ProjectionResidual<N>(K_, X_c, obs_, s_, residuals, &de_dXc)) return false;
  if (want_pose) {
    Eigen::Map<Eigen::Matrix<double, N, 7, Eigen::RowMajor>> J(jacobians[0]);
    J.template leftCols<3>() = -de_dXc * Skew(X_c);
    J.template middleCols<3>(3) = de_dXc;
    J.col(6).setZero();
  }
  if (want_point) {
    Eigen::Map<Eigen::Matrix<double, N, 3, Eigen::RowMajor>> J(jacobians[1]);
    J = de_dXc * q.toRotationMatrix();
  }
  return true;
}

template <int N>
bool RawResidual(const Intrinsics& K, const SE3& T_cw, const Eigen::Vector3d& X_w,
                 const Eigen::Vector3d& obs, double* e) {
  return ProjectionResidual<N>(K, T_cw * X_w, obs, 1.0, e, nullptr);
}

double HuberRho(double s, double delta2) {
  if (s <= delta2) return s;
  return 2.0 * std::sqrt(s * delta2) - delta2;
}

EdgeModel MakeEdgeModel(const Eigen::Vector2d& uv, double u_right, double inv_sigma2, double weight,
                        double chi2_mono, double chi2_stereo, bool weighted_test) {
  EdgeModel e;
  e.stereo = u_right >= 0;
  e.obs = Eigen::Vector3d(uv.x(), uv.y(), u_right);
  e.info = inv_sigma2 * weight;
  e.test_info = weighted_test ? e.info : inv_sigma2;
  e.threshold = e.stereo ? chi2_stereo : chi2_mono;
  return e;
}

double EdgeChi2(const Intrinsics& K, const SE3& T_cw, const Eigen::Vector3d& X_w,
                const EdgeModel& edge, std::vector<double>* raw, double* weighted_chi2) {
  double e[3] = {0, 0, 0};
  const int dof = edge.stereo ? 3 : 2;
  const bool ok = edge.stereo ? RawResidual<3>(K, T_cw, X_w, edge.obs, e)
                              : RawResidual<2>(K, T_cw, X_w, edge.obs, e);
  if (raw != nullptr) raw->assign(e, ok ? e + dof : e);
  if (!ok) {
    if (weighted_chi2 != nullptr) *weighted_chi2 = std::numeric_limits<double>::infinity();
    return std::numeric_limits<double>::infinity();
  }
  double sq = 0;
  for (int k = 0; k < dof; ++k) sq += e[k] * e[k];
  if (weighted_chi2 != nullptr) *weighted_chi2 = edge.info * sq;
  return edge.test_info * sq;
}

std::string LinkStage(const std::string& call_id) {
  return call_id.substr(0, call_id.find('#')) + ".obs";
}

void WriteResidualLink(trace::TraceWriter& trace, const std::string& link_stage, int kind,
                       const std::string& obs_id, const char* index_name, int64_t index,
                       std::initializer_list<std::pair<const char*, double>> more) {
  if (index < 0) return;
  std::vector<trace::NamedValue> inputs;
  inputs.reserve(1 + more.size());
  inputs.push_back({index_name, static_cast<double>(index)});
  for (const auto& [name, value] : more) inputs.push_back({name, value});
  trace.ProbabilityUpdate(link_stage, static_cast<trace::EntityKind>(kind), obs_id, inputs, 0.0, 0.0);
}

template class PoseOnlyCost<2>;
template class PoseOnlyCost<3>;
template class BACost<2>;
template class BACost<3>;
template bool RawResidual<2>(const Intrinsics&, const SE3&, const Eigen::Vector3d&,
                             const Eigen::Vector3d&, double*);
template bool RawResidual<3>(const Intrinsics&, const SE3&, const Eigen::Vector3d&,
                             const Eigen::Vector3d&, double*);

}  // namespace dynref::optim
