// Synthetic pose-only and local-BA problems with known ground truth, for tests/optim and
// bench_optim. All randomness from dynref::Rng streams "optim.synthetic.*".
#pragma once
#include <cstdint>
#include <vector>

#include "optim/optim.h"

namespace dynref::optim {

// TUM fr1-like pinhole (ORB-SLAM2 TUM1.yaml: bf = 40).
Intrinsics SyntheticIntrinsics();

struct SyntheticPoseSpec {
  int num_points = 200;
  double noise_px = 0.5;       // keypoint noise std at octave 0 (scaled by 1.2^octave)
  double outlier_ratio = 0.2;  // fraction of observations replaced by a random pixel
  bool stereo = true;          // rgbd3 residuals (u_right >= 0) or mono2 only
  int num_octaves = 8;         // octave drawn uniformly in [0, num_octaves)
  uint64_t seed = 1;
};

struct SyntheticPoseProblem {
  SE3 T_cw_true = SE3::Identity();
  SE3 T_cw_init = SE3::Identity();  // T_cw_true perturbed by ~3 cm / ~2 deg
  std::vector<PoseObservation> observations;
  std::vector<uint8_t> is_outlier;  // ground truth per observation
};

SyntheticPoseProblem MakeSyntheticPoseProblem(const SyntheticPoseSpec& spec);

struct SyntheticBASpec {
  int num_keyframes = 10;
  int num_fixed = 2;  // the first num_fixed keyframes are fixed (and unperturbed)
  int num_points = 3000;
  int views_per_point = 5;  // consecutive keyframes observing each point (if in the image)
  double noise_px = 0.5;
  double outlier_ratio = 0.02;
  double pose_noise_m = 0.01;  // perturbation of free keyframes (translation std)
  double pose_noise_rad = 0.005;
  double point_noise_m = 0.02;  // perturbation of points
  uint64_t seed = 1;
};

struct SyntheticBAProblem {
  std::vector<BAKeyFrame> keyframes;  // perturbed initial estimate
  std::vector<BAPoint> points;        // perturbed initial estimate
  std::vector<BAObservation> observations;
  std::vector<SE3> T_cw_true;             // per keyframe (same order)
  std::vector<Eigen::Vector3d> X_w_true;  // per point (same order)
  std::vector<uint8_t> is_outlier;        // per observation
};

SyntheticBAProblem MakeSyntheticBAProblem(const SyntheticBASpec& spec);

// Root-mean-square raw reprojection error (px, over u and v only) of the given observations at
// the given estimate; observations with mask[i] == 0 are skipped (mask empty = use all).
double RmsReprojectionPx(const Intrinsics& K, const std::map<int64_t, SE3>& T_cw,
                         const std::map<int64_t, Eigen::Vector3d>& X_w,
                         const std::vector<BAObservation>& observations,
                         const std::vector<uint8_t>& mask);

}  // namespace dynref::optim
