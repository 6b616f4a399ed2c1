// Map quality against the synthetic ground truth (issue 16; what no seed paper reports):
//   accuracy      distance of every map point to the nearest static surface (gt/static_scene.ply,
//                 exact point-to-triangle distance): mean, median, 95th percentile;
//   completeness  share of the static surface the camera saw (gt/static_observed.ply, 2 cm voxel
//                 centres) with a map point within `complete_m`;
//   ghosts        map points within `ghost_m` of a mover's observed surface at any time
//                 (gt/movers_observed.ply) and farther than `ghost_m` from every static surface.
// The caller moves map points into the ground-truth frame first (`dynref map-eval`: the run's
// first camera onto its true pose by default, or the trajectory's SE(3) ATE fit).
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/se3.h"
#include "eval/statistics.h"
#include "io/ply.h"
#include "io/trajectory.h"

namespace dynref {

struct MapEvalOptions {
  double complete_m = 0.05;  // issue 16: completeness at 5 cm
  double ghost_m = 0.05;     // issue 16: ghost = within 5 cm of a mover, farther than 5 cm from static
  double sample_m = 0.02;    // triangle sampling of the mesh index (exact distances are computed after)
};

struct MapEvalResult {
  size_t map_points = 0;
  ErrorStats accuracy;        // metres, over every map point
  double accuracy_p95 = 0;    // 95th percentile (linear interpolation, numpy default)
  size_t observed = 0, observed_covered = 0;
  double completeness = 0;    // observed_covered / observed
  size_t ghosts = 0;
  double ghost_fraction = 0;  // ghosts / map_points
};

// Exact distance from points to a triangle mesh (k-d tree over triangle samples, then the exact
// closest point of every candidate triangle; Ericson, Real-Time Collision Detection, 5.1.5).
class MeshDistance {
 public:
  MeshDistance(const TriangleMesh& mesh, double sample_m);
  ~MeshDistance();
  double Distance(const Eigen::Vector3d& q) const;

 private:
  struct Impl;
  const TriangleMesh& mesh_;
  double sample_m_;
  Impl* impl_;
};

// Closest point to p on triangle (a, b, c) (exposed for tests).
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

// The transform from a run's world frame (its map's frame) to the ground truth's.
//   kFirstCamera: the run's first camera (earliest pose associated with ground truth, TUM
//                 associate) onto its true pose, T = T_wc_gt T_wc_est^-1: the map's own anchor.
//   kAte:         the trajectory's SE(3) position fit (evaluate_ate.py), whose rotation a short or
//                 nearly straight camera path barely constrains.
// ate_rmse (optional) receives the trajectory's ATE RMSE. InputError when nothing associates.
enum class MapAlign { kFirstCamera, kAte };
SE3 MapToGroundTruth(const TumTrajectory& gt, const TumTrajectory& est, MapAlign mode, double* ate_rmse = nullptr);

// `map` already in the ground-truth frame; static_distance built on the static scene mesh (build it
// once when several maps of one sequence are evaluated).
MapEvalResult EvaluateMap(const std::vector<Eigen::Vector3d>& map, const MeshDistance& static_distance,
                          const PointCloud& static_observed, const PointCloud& movers,
                          const MapEvalOptions& options);
// The same, building the mesh index with options.sample_m.
MapEvalResult EvaluateMap(const std::vector<Eigen::Vector3d>& map, const TriangleMesh& static_mesh,
                          const PointCloud& static_observed, const PointCloud& movers,
                          const MapEvalOptions& options);

}  // namespace dynref
