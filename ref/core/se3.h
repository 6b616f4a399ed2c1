// Rigid transforms. Names say what they map: T_wc = world_from_camera (camera-to-world, TUM
// groundtruth convention), T_cw = camera_from_world (ORB-SLAM's stored pose).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dynref {

using SE3 = Eigen::Isometry3d;

// A stamped pose as it appears in a TUM trajectory line: "t tx ty tz qx qy qz qw".
struct StampedPose {
  double stamp = 0.0;
  SE3 T_wc = SE3::Identity();
};

// Builds an SE3 from translation and a unit quaternion (x, y, z, w order as in TUM files).
SE3 MakeSE3(const Eigen::Vector3d& t, const Eigen::Quaterniond& q);
// Rotation angle of R in radians, robust near 0 and pi (clamped acos of (trace-1)/2).
double RotationAngleRad(const Eigen::Matrix3d& R);

}  // namespace dynref
