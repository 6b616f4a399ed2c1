// Planted poses of the loop room's tests: a yaw about the camera's y axis and a translation.
#pragma once
#include <Eigen/Geometry>

#include "core/se3.h"

namespace dynref::test {

inline SE3 YawPose(double yaw, const Eigen::Vector3d& t) {
  SE3 T = SE3::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = t;
  return T;
}

}  // namespace dynref::test
