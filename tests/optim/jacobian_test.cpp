// Each cost functor's analytic Jacobian (times the manifold's PlusJacobian, the product Ceres
// uses) against central numeric differences of e(Plus(x, delta)) and e(X_w + d).
#include <catch2/catch.hpp>
#include <cmath>

#include "core/rng.h"
#include "optim/reprojection.h"
#include "optim/synthetic_problem.h"

using namespace dynref;
using namespace dynref::optim;

namespace {

using MatrixXdRow = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

SE3 SomePose(Rng& rng) {
  Eigen::Matrix<double, 6, 1> xi;
  for (int k = 0; k < 6; ++k) xi[k] = rng.Uniform(-0.5, 0.5);
  return ExpSE3(xi);
}

// Checks d e / d delta (pose tangent) and, when `point` is non-null, d e / d X_w.
void CheckFunctor(const ceres::CostFunction& cost, int num_residuals, double* pose7,
                  double* point3) {
  const PoseManifold manifold;
  std::vector<double*> params = {pose7};
  if (point3 != nullptr) params.push_back(point3);
  std::vector<double> e0(num_residuals);
  MatrixXdRow J_pose_ambient(num_residuals, 7), J_point(num_residuals, 3);
  double* jacobians[2] = {J_pose_ambient.data(), J_point.data()};
  REQUIRE(cost.Evaluate(params.data(), e0.data(), jacobians));
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus_jacobian;
  REQUIRE(manifold.PlusJacobian(pose7, plus_jacobian.data()));
  const Eigen::MatrixXd J_pose = J_pose_ambient * plus_jacobian;

  const double h = 1e-6;
  std::vector<double> ep(num_residuals), em(num_residuals);
  for (int k = 0; k < 6; ++k) {
    double delta[6] = {0, 0, 0, 0, 0, 0}, xp[7], xm[7];
    delta[k] = h;
    manifold.Plus(pose7, delta, xp);
    delta[k] = -h;
    manifold.Plus(pose7, delta, xm);
    std::vector<double*> pp = params, pm = params;
    pp[0] = xp;
    pm[0] = xm;
    REQUIRE(cost.Evaluate(pp.data(), ep.data(), nullptr));
    REQUIRE(cost.Evaluate(pm.data(), em.data(), nullptr));
    for (int r = 0; r < num_residuals; ++r) {
      const double numeric = (ep[r] - em[r]) / (2 * h);
      INFO("pose tangent " << k << " residual " << r);
      CHECK(J_pose(r, k) == Approx(numeric).margin(1e-5).epsilon(1e-5));
    }
  }
  if (point3 == nullptr) return;
  for (int k = 0; k < 3; ++k) {
    double Xp[3] = {point3[0], point3[1], point3[2]}, Xm[3] = {point3[0], point3[1], point3[2]};
    Xp[k] += h;
    Xm[k] -= h;
    std::vector<double*> pp = {pose7, Xp}, pm = {pose7, Xm};
    REQUIRE(cost.Evaluate(pp.data(), ep.data(), nullptr));
    REQUIRE(cost.Evaluate(pm.data(), em.data(), nullptr));
    for (int r = 0; r < num_residuals; ++r) {
      const double numeric = (ep[r] - em[r]) / (2 * h);
      INFO("point coordinate " << k << " residual " << r);
      CHECK(J_point(r, k) == Approx(numeric).margin(1e-5).epsilon(1e-5));
    }
  }
}

// A world point in front of T_cw at a few metres.
Eigen::Vector3d PointInFront(const SE3& T_cw, Rng& rng) {
  const Eigen::Vector3d X_c(rng.Uniform(-1, 1), rng.Uniform(-0.8, 0.8), rng.Uniform(0.6, 4.0));
  return T_cw.inverse() * X_c;
}

}  // namespace

TEST_CASE("jacobian: pose-only rgbd3 and mono2 functors match numeric differentiation") {
  Rng rng(5, "optim.test.jacobian");
  const Intrinsics K = SyntheticIntrinsics();
  for (int trial = 0; trial < 20; ++trial) {
    const SE3 T_cw = SomePose(rng);
    double pose[7];
    PoseToParams(T_cw, pose);
    const Eigen::Vector3d X_w = PointInFront(T_cw, rng);
    const Eigen::Vector3d obs(rng.Uniform(0, 640), rng.Uniform(0, 480), rng.Uniform(0, 600));
    const double s = rng.Uniform(0.3, 1.0);
    CheckFunctor(PoseOnlyCost<3>(K, X_w, obs, s), 3, pose, nullptr);
    CheckFunctor(PoseOnlyCost<2>(K, X_w, obs, s), 2, pose, nullptr);
  }
}

TEST_CASE("jacobian: local-BA rgbd3 and mono2 functors match numeric differentiation") {
  Rng rng(6, "optim.test.jacobian");
  const Intrinsics K = SyntheticIntrinsics();
  for (int trial = 0; trial < 20; ++trial) {
    const SE3 T_cw = SomePose(rng);
    double pose[7];
    PoseToParams(T_cw, pose);
    const Eigen::Vector3d X_w = PointInFront(T_cw, rng);
    double point[3] = {X_w.x(), X_w.y(), X_w.z()};
    const Eigen::Vector3d obs(rng.Uniform(0, 640), rng.Uniform(0, 480), rng.Uniform(0, 600));
    const double s = rng.Uniform(0.3, 1.0);
    CheckFunctor(BACost<3>(K, obs, s), 3, pose, point);
    CheckFunctor(BACost<2>(K, obs, s), 2, pose, point);
  }
}

TEST_CASE("jacobian: pose manifold Plus/Minus are inverse and Exp/Log round-trip") {
  Rng rng(7, "optim.test.manifold");
  const PoseManifold manifold;
  for (int trial = 0; trial < 20; ++trial) {
    double x[7], y[7], d[6], back[6];
    PoseToParams(SomePose(rng), x);
    for (double& v : d) v = rng.Uniform(-0.3, 0.3);
    REQUIRE(manifold.Plus(x, d, y));
    REQUIRE(manifold.Minus(y, x, back));
    for (int k = 0; k < 6; ++k) CHECK(back[k] == Approx(d[k]).margin(1e-12));
    const Eigen::Matrix<double, 6, 1> xi = Eigen::Map<Eigen::Matrix<double, 6, 1>>(d);
    CHECK((LogSE3(ExpSE3(xi)) - xi).norm() < 1e-12);
  }
}

TEST_CASE("jacobian: a point behind the camera makes the functor fail (step rejected)") {
  const Intrinsics K = SyntheticIntrinsics();
  double pose[7];
  PoseToParams(SE3::Identity(), pose);
  const PoseOnlyCost<3> cost(K, Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(300, 200, 280), 1.0);
  double* params[1] = {pose};
  double e[3];
  CHECK_FALSE(cost.Evaluate(params, e, nullptr));
}
