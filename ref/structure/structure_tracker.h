// Lines and planes in the backbone (seed 000 Sec. 3.2-3.6, spec 000 steps 3, 4, 14; issue 13):
// extraction into the frame, association with map landmarks at the current pose estimate,
// landmark creation at keyframes, the local-BA part and map maintenance (line culling, plane
// merging). The tracker and the local mapper call it only when a config enables lines or planes.
//
// Choices the spec leaves open (each also in ref/structure/README.md):
// - A sample's depth is the nearest valid depth in a 5 x 5 window around it (segments lie on
//   depth edges; the nearest surface is the one the edge belongs to). A segment whose three
//   samples do not all have depth, are not collinear in 3-D or are shorter than 5 cm in 3-D is
//   still associated and used in pose optimisation (its residual needs only the 2-D line) but
//   never creates a map line.
// - Association is greedy over candidate pairs sorted by (distance, map id, frame index): a map
//   line / plane takes at most one frame line / plane and vice versa.
// - A map line created at keyframe k is culled when, 3 keyframes later, fewer than 2 keyframes
//   observe it (ORB-SLAM2 MapPointCulling's rule for points).
// - Map planes observed by the local keyframes merge when their normals and distances agree
//   (the older id survives, event kReplaced).
#pragma once
#include <set>
#include <vector>

#include "io/camera.h"
#include "map/map.h"
#include "optim/optim.h"
#include "structure/structure_options.h"
#include "trace/trace_writer.h"

namespace dynref::structure {

class StructureTracker {
 public:
  StructureTracker(const Camera& camera, const StructureOptions& options, trace::TraceWriter& trace);
  const StructureOptions& options() const { return o_; }

  // Segments (on f.grey, after the before_extraction stages) and planes (on f.depth_m).
  // CPU ms of the segment and plane parts are added to *lines_ms / *planes_ms when non-null.
  void Extract(Frame& f, double* lines_ms = nullptr, double* planes_ms = nullptr) const;
  // Associates f's lines and planes with good map landmarks at f.T_cw (replacing earlier
  // associations); returns the weighted association count.
  double Associate(Frame& f, const Map& map) const;
  // Pose-only part of f's associations; line_index / plane_index give the frame feature of each.
  optim::PoseStructure BuildPoseStructure(const Frame& f, const Map& map, std::vector<int>* line_index,
                                          std::vector<int>* plane_index) const;
  // Writes the pose-only classification into f (outlier flags).
  void ApplyPoseResult(Frame& f, const optim::PoseOnlyResult& r, const std::vector<int>& line_index,
                       const std::vector<int>& plane_index) const;
  // Weighted count of associated, non-outlier lines and planes.
  double InlierCount(const Frame& f) const;
  // Removes outlier associations (ORB-SLAM2 discards outlier matches after pose optimisation).
  void DiscardOutliers(Frame& f) const;
  // Keyframe kf (made from f): observations of associated landmarks, new map lines / planes for
  // the others. Trace counts "structure.keyframe" new_lines, new_planes.
  void CreateLandmarks(Frame& f, KeyFrame& kf, Map& map) const;

  // Local BA: structure landmarks seen by `local` keyframes, their observations; keyframes
  // outside `local` that observe them join `fixed`.
  void FillLocalBA(const Map& map, const std::set<int64_t>& local, std::set<int64_t>* fixed,
                   optim::LocalBAStructure* st) const;
  // Writes BA results back (outlier observations erased, landmark parameters updated); returns
  // the number of outlier observations.
  int ApplyLocalBA(Map& map, const optim::LocalBAStructure& st, const optim::LocalBAResult& r) const;
  // Landmark parameters only (no observation erased): ApplyLocalBA's last step, and loop
  // closing's global BA (ORB-SLAM2's global BA flags no outlier, ref/loop/global_ba.h).
  void ApplyLandmarks(Map& map, const optim::LocalBAResult& r) const;
  // Full trace: one geometry record per frame line and plane (PROB, stage "structure", p = 0:
  // the backbone treats every line and plane as static; ref/trace/README.md), after tracking.
  void TraceFrame(const Frame& f) const;
  // Line culling and plane merging after keyframe kf_id's local mapping.
  void MaintainMap(Map& map, int64_t kf_id, const std::set<int64_t>& local) const;

 private:
  const Camera& camera_;
  StructureOptions o_;
  trace::TraceWriter& trace_;
};

}  // namespace dynref::structure
