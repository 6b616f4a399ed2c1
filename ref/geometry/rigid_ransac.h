// Relative pose of two RGB-D frames from 3-D point pairs (seed 004 Module C: "R, t from the static
// region's matches"), by RANSAC over minimal 3-point samples (Umeyama / Kabsch, no scale) and a
// least-squares refit on the inliers. Inlier: the previous-frame point, moved by (R, t), projects
// within `inlier_px` of its current pixel. Every draw from the caller's dynref Rng.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/rng.h"

namespace dynref::geometry {

struct PointPair3D {
  Eigen::Vector3d X_prev;  // in the previous camera frame (metres)
  Eigen::Vector3d X_cur;   // the same point in the current camera frame
  Eigen::Vector2d u_cur;   // its pixel in the current image
};

struct RigidRansacOptions {
  double inlier_px = 2.0;      // reprojection gate (not stated)
  int iterations = 200;        // fixed budget (not stated)
  int min_inliers = 12;        // below this the pose is not trusted (not stated)
  void Check() const;          // std::invalid_argument naming the field
};

struct RigidRansacResult {
  bool valid = false;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // T_cur_prev: X_cur = R X_prev + t
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  std::vector<uint8_t> inliers;
  int inlier_count = 0;
};

RigidRansacResult RigidRansac(const std::vector<PointPair3D>& pairs, double fx, double fy, double cx, double cy,
                              const RigidRansacOptions& o, Rng& rng);

}  // namespace dynref::geometry
