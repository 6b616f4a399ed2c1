// Local map tracking (ORB-SLAM2 Tracking::TrackLocalMap): the local keyframes and points
// (UpdateLocalMap), the projection search (SearchLocalPoints) and the final pose with its success
// test; see tracker.h.
#include <map>

#include "tracking/matcher.h"
#include "tracking/tracker.h"

namespace dynref::tracking {

// Keyframe id -> how many of f's associated map points it observes; associations to bad points
// are dropped.
std::map<int64_t, int> Tracker::CountObservingKeyFrames(Frame& f) {
  std::map<int64_t, int> counter;
  for (size_t i = 0; i < f.N(); ++i) {
    const int64_t id = f.map_point_ids[i];
    if (id < 0) continue;
    const MapPoint* p = map_.good_mp(id);
    if (p == nullptr) {
      f.map_point_ids[i] = -1;
      continue;
    }
    for (const auto& kv : p->observations) counter[kv.first]++;
  }
  return counter;
}

void Tracker::UpdateLocalKeyFrames(Frame& f) {
  const std::map<int64_t, int> counter = CountObservingKeyFrames(f);
  if (counter.empty()) return;
  local_kfs_.clear();
  int max = 0;
  int64_t kf_max = -1;
  for (const auto& [id, n] : counter) {
    KeyFrame* k = map_.kf(id);
    if (k == nullptr || k->bad) continue;
    if (n > max) {
      max = n;
      kf_max = id;
    }
    local_kfs_.push_back(id);
    k->track_ref_frame = f.index;
  }
  AddNeighbourKeyFrames(f.index);
  if (kf_max >= 0) reference_kf_ = kf_max;
}

// ORB-SLAM2 Tracking::UpdateLocalKeyFrames expands only the keyframes that observe a matched
// point (its loop end is fixed before the neighbours are appended), and adding a parent ends the
// expansion (the break there leaves the outer loop).
void Tracker::AddNeighbourKeyFrames(int frame_index) {
  auto add = [&](int64_t id) {
    KeyFrame* k = map_.kf(id);
    if (k == nullptr || k->bad || k->track_ref_frame == frame_index) return false;
    k->track_ref_frame = frame_index;
    local_kfs_.push_back(id);
    return true;
  };
  const size_t n_observing = local_kfs_.size();
  for (size_t j = 0; j < n_observing; ++j) {
    if (local_kfs_.size() > 80) break;  // ORB-SLAM2 limit
    const KeyFrame* k = map_.kf(local_kfs_[j]);
    for (int64_t n : k->BestCovisibles(10))
      if (add(n)) break;
    for (const auto& kv : map_.keyframes)
      if (kv.second->parent == k->id && add(kv.first)) break;
    if (k->parent >= 0 && add(k->parent)) break;
  }
}

// The good map points of the local keyframes, each once (ORB-SLAM2 UpdateLocalPoints).
std::vector<int64_t> Tracker::LocalPoints(int frame_index) {
  std::vector<int64_t> local_points;
  for (int64_t kf_id : local_kfs_) {
    const KeyFrame* k = map_.kf(kf_id);
    for (int64_t id : k->map_point_ids) {
      if (id < 0) continue;
      MapPoint* p = map_.good_mp(id);
      if (p == nullptr || p->track_ref_frame == frame_index) continue;
      p->track_ref_frame = frame_index;
      local_points.push_back(id);
    }
  }
  return local_points;
}

// ORB-SLAM2 SearchLocalPoints: the points already matched count as visible and seen; the
// others that project into the frame are candidates for the projection search.
std::vector<ProjectedPoint> Tracker::LocalPointsInView(Frame& f, const std::vector<int64_t>& local_points) {
  for (size_t i = 0; i < f.N(); ++i) {
    const int64_t id = f.map_point_ids[i];
    if (id < 0) continue;
    MapPoint* p = map_.good_mp(id);
    if (p == nullptr) {
      f.map_point_ids[i] = -1;
      continue;
    }
    p->visible++;
    p->last_seen_frame = f.index;
  }
  std::vector<ProjectedPoint> projected;
  for (int64_t id : local_points) {
    MapPoint* p = map_.mp(id);
    if (p->last_seen_frame == f.index) continue;
    ProjectedPoint pp;
    if (IsInFrustum(f, *p, &pp)) {
      p->visible++;
      projected.push_back(pp);
    }
  }
  return projected;
}

void Tracker::SearchLocalMap(Frame& f) {
  UpdateLocalKeyFrames(f);
  const std::vector<int64_t> local_points = LocalPoints(f.index);
  const std::vector<ProjectedPoint> projected = LocalPointsInView(f, local_points);
  int n = 0;
  if (!projected.empty()) {
    float th = 3;  // ORB-SLAM2 SearchLocalPoints: RGB-D th = 3, 5 right after relocalisation
    if (f.index < last_reloc_frame_ + 2) th = 5;
    n = SearchByProjectionLocal(f, projected, map_, th);
  }
  trace_.FrameCount("track.local_map", "keyframes", static_cast<int64_t>(local_kfs_.size()));
  trace_.FrameCount("track.local_map", "points_in_view", static_cast<int64_t>(projected.size()));
  trace_.FrameCount("track.local_map", "new_matches", n);
}

bool Tracker::OptimizeFinal(Frame& f) {
  OptimizePose(f);
  matches_inliers_ = 0;
  for (size_t i = 0; i < f.N(); ++i) {
    const int64_t id = f.map_point_ids[i];
    if (id < 0 || f.outlier[i]) continue;
    MapPoint* p = map_.good_mp(id);
    if (p == nullptr) continue;
    p->found++;
    if (p->n_obs > 0) ++matches_inliers_;
  }
  trace_.FrameCount("track.final", "inliers", matches_inliers_);
  structure_inliers_ = structure_ != nullptr ? StructureCount(structure_->InlierCount(f)) : 0;
  if (structure_ != nullptr) trace_.FrameCount("track.final", "structure_inliers", structure_inliers_);
  const int inliers = matches_inliers_ + structure_inliers_;
  if (f.index < last_reloc_frame_ + options_.max_frames && inliers < 50) return false;
  if (inliers < 30) return false;
  // ORB-SLAM2 Tracking::Track updates the motion model right after TrackLocalMap, with the last
  // frame pose used for tracking this frame, i.e. before local mapping moves its reference KF.
  if (has_last_ && last_.has_pose) {
    velocity_ = f.T_cw * last_.T_cw.inverse();
    has_velocity_ = true;
  } else {
    has_velocity_ = false;
  }
  return true;
}

}  // namespace dynref::tracking
