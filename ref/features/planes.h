// Plane segmentation of an organised RGB-D cloud by agglomerative hierarchical clustering (AHC;
// Feng, Taguchi & Kamat, ICRA 2014, "PEAC"), written for dynref (seed 000 Sec. 3.2, spec 000
// step 4; issue 13). Three phases, as in the paper:
//  1. block initialisation: the (strided) depth image is cut into square blocks; a block becomes a
//     graph node when all its points have depth, no depth discontinuity lies inside it and its
//     least-squares plane fits with MSE <= T_mse(z) = (sigma_z(z) + tol_init)^2, where
//     sigma_z(z) = depth_sigma z^2 (Kinect depth noise grows with z^2);
//  2. agglomerative merging: repeatedly take the node with the smallest MSE, merge it with the
//     4-neighbour whose union fits best (normals within merge_angle_deg); when even that union
//     fits worse than (sigma_z + tol_merge)^2 the node leaves the graph and becomes a plane if it
//     has min_support points;
//  3. refinement: the points of the blocks bordering a plane that lie within
//     3 (sigma_z + tol_init) of it join it; each plane is refitted on its points.
// Then coplanar patches merge (normals within coplanar_angle_deg, |d_a - d_b| <= coplanar_dist_m).
// A plane is kept when its metric footprint sum_i Z_i^2 / (fx fy) (pixel area at depth Z) is at
// least T_plane = 0.05 m^2 (spec 000 (c), the paper's "approx. 0.05 m^2 in image space").
// Plane convention: n^T X + d = 0 in the camera frame, n unit, oriented towards the camera (d > 0).
// Deterministic: ties in the merge order break by node id.
#pragma once
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "core/intrinsics.h"

namespace dynref::features {

struct PlaneOptions {
  int stride = 2;                 // sample every stride-th pixel (speed; not in the paper)
  int block = 10;                 // block side in samples (PEAC windowWidth/Height = 10)
  double depth_sigma = 1.6e-3;    // sigma_z = depth_sigma z^2, 1/m (PEAC depthSigma 1.6e-6 /mm)
  double tol_init_m = 0.005;      // PEAC stdTol_init 5 mm
  double tol_merge_m = 0.008;     // PEAC stdTol_merge 8 mm
  double merge_angle_deg = 60;    // PEAC similarityTh_merge = cos 60 deg
  int min_support = 3000;         // full-resolution pixels (PEAC minSupport)
  double min_area_m2 = 0.05;      // T_plane (spec 000 (c))
  double max_depth_m = 4.0;       // PEAC z_far 4000 mm
  double coplanar_angle_deg = 5;  // patches this parallel ...
  double coplanar_dist_m = 0.05;  // ... and this close in d are one plane (not stated)
  int max_planes = 20;            // keep the largest
  void Check() const;             // std::invalid_argument naming the field
};

struct PlaneObservation {
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();  // unit normal, camera frame, towards the camera
  double d = 0;                                  // n^T X + d = 0 (d > 0: distance from the camera)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  int points = 0;          // sampled points after refinement
  double area_m2 = 0;      // metric footprint
  double mse = 0;          // mean squared point-plane distance, m^2
};

struct PlaneSegmentation {
  std::vector<PlaneObservation> planes;  // by points descending (ties: lower label first)
  cv::Mat labels;  // CV_16S at full resolution, -1 = no plane, else index into planes
};

PlaneSegmentation SegmentPlanes(const cv::Mat& depth_m, const Intrinsics& K, const PlaneOptions& options);

// Least-squares plane of accumulated points (exposed for tests): normal = eigenvector of the
// smallest eigenvalue of the scatter matrix, mse = that eigenvalue / n.
struct PlaneFitSums {
  double n = 0;
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();
  void Add(const Eigen::Vector3d& p) { n += 1, s += p, ss += p * p.transpose(); }
  void Add(const PlaneFitSums& o) { n += o.n, s += o.s, ss += o.ss; }
};
// Returns false when fewer than 3 points.
bool FitPlane(const PlaneFitSums& sums, Eigen::Vector3d* normal, double* d, double* mse);

}  // namespace dynref::features
