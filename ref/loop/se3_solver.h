// ORB-SLAM2 Sim3Solver with fixed scale (RGB-D: bFixScale = true), i.e. an SE(3) RANSAC between
// two keyframes (Mur-Artal & Tardos, T-RO 2017, Sec. V-B "compute the similarity transformation";
// Horn, "Closed-form solution of absolute orientation using unit quaternions", JOSA A 1987, here
// through the SVD form with fixed scale, Umeyama 1991):
//  - input: matched map points as 3-D points in each keyframe's camera (X1 = T_1w X, X2 = T_2w X'),
//    and both keypoints with their level sigma^2;
//  - minimal sets of 3 correspondences drawn from the seeded stream (Rng(seed, "loop.se3"));
//  - inlier: the reprojection of T_12 X2 into image 1 and of T_21 X1 into image 2 within
//    chi2 9.210 * sigma^2 (ORB-SLAM2 mvnMaxError1/2 = 9.210 * sigma^2, 99 % for 2 dof);
//  - RANSAC(probability 0.99, min inliers 20, max iterations 300) as LoopClosing::ComputeSim3 sets
//    it; the iteration count shrinks as ORB-SLAM2's: ceil(log(1 - p) / log(1 - (min_inliers / N)^3));
//  - the best model's inliers are refitted once (ORB-SLAM2 refines with OptimizeSim3; here the
//    closed form over all inliers, kept when it does not lose inliers).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/intrinsics.h"
#include "core/rng.h"
#include "core/se3.h"

namespace dynref::loop {

struct Se3Match {
  Eigen::Vector3d X1 = Eigen::Vector3d::Zero(), X2 = Eigen::Vector3d::Zero();  // in camera 1 / 2
  Eigen::Vector2d uv1 = Eigen::Vector2d::Zero(), uv2 = Eigen::Vector2d::Zero();
  double sigma2_1 = 1, sigma2_2 = 1;
};

struct Se3RansacOptions {
  double probability = 0.99;
  int min_inliers = 20;
  int max_iterations = 300;
  double chi2 = 9.210;
};

struct Se3RansacResult {
  bool ok = false;
  SE3 T_12 = SE3::Identity();  // camera 2 -> camera 1
  std::vector<uint8_t> inlier;
  int num_inliers = 0;
  int iterations = 0;
};

// The rigid transform minimising sum |X1_i - (R X2_i + t)|^2 (needs >= 3 non-collinear points).
SE3 AlignRigid(const std::vector<Eigen::Vector3d>& X1, const std::vector<Eigen::Vector3d>& X2);

Se3RansacResult Se3Ransac(const std::vector<Se3Match>& matches, const Intrinsics& K, const Se3RansacOptions& options,
                          Rng& rng);

// Inliers of T_12 (both reprojection tests); returns their count.
int Se3Inliers(const std::vector<Se3Match>& matches, const Intrinsics& K, const SE3& T_12, double chi2,
               std::vector<uint8_t>* inlier);

}  // namespace dynref::loop
