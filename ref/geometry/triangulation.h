// Linear (DLT) two-view triangulation (Hartley & Zisserman 12.2), shared by ORB-SLAM2's
// LocalMapping::CreateNewMapPoints (ref/mapping) and seed 004's NeRF export (ref/dynamic/epi).
#pragma once
#include <Eigen/Core>
#include <Eigen/SVD>

namespace dynref::geometry {

// Rows u P^3 - P^1, v P^3 - P^2 of both views; X = the right singular vector of the smallest
// singular value, dehomogenised. P0, P1 are 3x4 projections and x0, x1 observations in the same
// coordinates (pixels with K [R | t], normalised coordinates with [R | t]). False when the
// solution is at infinity (homogeneous w = 0).
inline bool TriangulateLinear(const Eigen::Matrix<double, 3, 4>& P0, const Eigen::Matrix<double, 3, 4>& P1,
                              const Eigen::Vector2d& x0, const Eigen::Vector2d& x1, Eigen::Vector3d* X) {
  Eigen::Matrix4d A;
  A.row(0) = x0.x() * P0.row(2) - P0.row(0);
  A.row(1) = x0.y() * P0.row(2) - P0.row(1);
  A.row(2) = x1.x() * P1.row(2) - P1.row(0);
  A.row(3) = x1.y() * P1.row(2) - P1.row(1);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d h = svd.matrixV().col(3);
  if (h(3) == 0) return false;
  *X = h.head<3>() / h(3);
  return true;
}

}  // namespace dynref::geometry
