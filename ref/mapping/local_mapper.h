// ORB-SLAM2 LocalMapping run sequentially after tracking, once per new keyframe: process the
// keyframe (observations, covisibility), cull recent map points, triangulate new points with the
// 10 best covisible keyframes, fuse duplicates with first/second-ring neighbours, local bundle
// adjustment (ref/optim, "localba#<n>"), keyframe culling (90 % redundant). Loop closing is off.
// Excluded features never create points or enter BA; per-observation weights (copied from the
// frame into the keyframe) multiply the BA information.
#pragma once
#include <cstdint>
#include <mutex>
#include <vector>

#include "features/mnn2.h"
#include "map/map.h"
#include "optim/optim.h"
#include "structure/structure_tracker.h"
#include "trace/trace_writer.h"

namespace dynref::mapping {

struct LocalMapperOptions {
  int covisible_for_triangulation = 10;  // ORB-SLAM2 nn = 10 (non-monocular)
  bool local_ba = true;
  bool keyframe_culling = true;
  double redundancy = 0.9;               // ORB-SLAM2 KeyFrameCulling: > 90 % redundant
  optim::LocalBAOptions ba;              // ORB-SLAM2 Optimizer::LocalBundleAdjustment (5 + 10 iterations)
  features::BackboneMnn2 mnn2;           // seed 004 MNN2 in the triangulation search (off: ORB-SLAM2)
  void Check() const;
};

struct LocalMapperStats {
  int culled_points = 0, new_points = 0, fused = 0, ba_outliers = 0, culled_keyframes = 0;
  // Size of the local BA problem (0 when none ran): what the virtual mapping clock charges.
  int ba_keyframes = 0, ba_points = 0, ba_observations = 0;
  double ba_ms = 0;                      // time inside LocalBundleAdjust (run.json only)
};

class LocalMapper {
 public:
  LocalMapper(Map& map, const Camera& camera, const LocalMapperOptions& options, trace::TraceWriter& trace);
  LocalMapperStats ProcessKeyFrame(int64_t kf_id);
  int ba_calls() const { return ba_calls_; }
  // Lines and planes (issue 13; nullptr = point-only). Not owned.
  void SetStructure(const structure::StructureTracker* s) { structure_ = s; }
  // --variant concurrent (issue 18): the held lock on the map that local BA releases while Ceres
  // solves (the problem is a copy; the result is written back under the lock again), as
  // ORB-SLAM2's LocalMapping does. nullptr (the oracle): never released.
  void SetMapLock(std::unique_lock<std::mutex>* lock) { map_lock_ = lock; }

 private:
  void ProcessNewKeyFrame(KeyFrame& kf);
  int MapPointCulling(const KeyFrame& kf);
  int CreateNewMapPoints(KeyFrame& kf);
  int SearchInNeighbors(KeyFrame& kf);
  int Fuse(KeyFrame& target, const std::vector<int64_t>& points, float th);
  int LocalBundleAdjustment(KeyFrame& kf, LocalMapperStats* stats);
  int KeyFrameCulling(const KeyFrame& kf);

  Map& map_;
  const Camera& camera_;
  LocalMapperOptions options_;
  trace::TraceWriter& trace_;
  std::vector<int64_t> recent_points_;
  int ba_calls_ = 0;
  const structure::StructureTracker* structure_ = nullptr;
  std::unique_lock<std::mutex>* map_lock_ = nullptr;
};

}  // namespace dynref::mapping
