#include "core/se3.h"

#include <algorithm>
#include <cmath>

namespace dynref {

SE3 MakeSE3(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  SE3 T = SE3::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

double RotationAngleRad(const Eigen::Matrix3d& R) {
  const double c = std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c);
}

}  // namespace dynref
