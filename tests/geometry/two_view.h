// Synthetic two-view geometry for the geometry tests: known K, known relative pose, points.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/rng.h"
#include "geometry/fundamental.h"

namespace dynref::geometry::testgeo {

inline Eigen::Matrix3d K() {
  Eigen::Matrix3d k;
  k << 535.4, 0, 320.1, 0, 539.2, 247.6, 0, 0, 1;
  return k;
}

// T_cur_prev: maps points from the previous camera frame into the current one.
inline Eigen::Isometry3d RelativePose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(-0.03, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.12, -0.02, 0.05);
  return T;
}

inline Eigen::Matrix3d Skew(const Eigen::Vector3d& t) {
  Eigen::Matrix3d S;
  S << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  return S;
}

// x_cur^T F x_prev = 0 for x_cur = K (R X + t), x_prev = K X.
inline Eigen::Matrix3d TrueF() {
  const Eigen::Isometry3d T = RelativePose();
  const Eigen::Matrix3d Kinv = K().inverse();
  Eigen::Matrix3d F = Kinv.transpose() * Skew(T.translation()) * T.linear() * Kinv;
  return F / F.norm();
}

inline Eigen::Vector2d Project(const Eigen::Vector3d& X) {
  const Eigen::Vector3d x = K() * X;
  return x.head<2>() / x.z();
}

struct Scene {
  std::vector<Correspondence> pairs;
  std::vector<bool> moving;
};

// n_static points at 1.5..4 m plus n_moving points that move by `motion_m` between the views.
inline Scene MakeScene(int n_static, int n_moving, double motion_m, uint64_t seed) {
  Rng rng(seed, "test.sgdo.scene");
  Scene s;
  const Eigen::Isometry3d T = RelativePose();
  for (int i = 0; i < n_static + n_moving; ++i) {
    const double z = rng.Uniform(1.5, 4.0);
    const Eigen::Vector3d X(rng.Uniform(-0.5, 0.5) * z, rng.Uniform(-0.4, 0.4) * z, z);
    Eigen::Vector3d X_cur = T * X;
    const bool moving = i >= n_static;
    if (moving) {
      // Motion mostly perpendicular to the viewing ray (walking person): vertical + sideways.
      X_cur += motion_m * Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(0.5, 1.0), 0).normalized();
    }
    s.pairs.push_back({Project(X), Project(X_cur)});
    s.moving.push_back(moving);
  }
  return s;
}

}  // namespace dynref::geometry::testgeo
