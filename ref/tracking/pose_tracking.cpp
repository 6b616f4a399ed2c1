// Initial pose of a frame (ORB-SLAM2 Tracking::TrackWithMotionModel, TrackReferenceKeyFrame) and
// the pose-only optimisation both use with the final pose (Optimizer::PoseOptimization); see
// tracker.h. Relocalisation: relocalise.cpp.
#include <algorithm>

#include "optim/optim.h"
#include "tracking/matcher.h"
#include "tracking/relocaliser_bow.h"
#include "tracking/tracker.h"

namespace dynref::tracking {

bool Tracker::TrackWithMotionModel(Frame& f) {
  UpdateLastFramePose();
  f.T_cw = velocity_ * last_.T_cw;
  std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  const float th = 15;  // ORB-SLAM2: th = 15 for non-stereo sensors (RGB-D)
  int n = SearchByProjectionLastFrame(f, last_, map_, th);
  if (n < 20) {
    std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
    n = SearchByProjectionLastFrame(f, last_, map_, 2 * th);
  }
  trace_.FrameCount("track.motion_model", "matches", n);
  if (structure_ != nullptr) n += StructureCount(structure_->Associate(f, map_));
  if (n < 20) return false;
  OptimizePose(f);
  return DiscardOutliers(f) >= 10;
}

bool Tracker::TrackReferenceKeyFrame(Frame& f) {
  const KeyFrame* ref = map_.kf(reference_kf_);
  if (ref == nullptr) return false;
  std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  int n = MatchReferenceKeyFrame(*ref, f, map_, options_, place_);  // relocaliser_bow.h
  trace_.FrameCount("track.reference_kf", "matches", n);
  if (structure_ != nullptr && n < 15) {
    f.T_cw = last_.T_cw;  // association needs a pose; the same start as below
    n += StructureCount(structure_->Associate(f, map_));
  }
  if (n < 15) return false;
  // ORB-SLAM2 TrackReferenceKeyFrame starts from the last frame's pose as it stands (refreshed
  // from its reference keyframe only if the motion model ran first and failed).
  f.T_cw = last_.T_cw;
  OptimizePose(f);
  return DiscardOutliers(f) >= 10;
}

// One observation per associated good map point of a non-excluded feature (`idx`: the feature);
// other associations are dropped.
std::vector<optim::PoseObservation> Tracker::PoseObservations(Frame& f, std::vector<int>* idx) {
  std::vector<optim::PoseObservation> obs;
  for (size_t i = 0; i < f.N(); ++i) {
    const int64_t id = f.map_point_ids[i];
    if (id < 0) continue;
    const MapPoint* p = map_.good_mp(id);
    if (p == nullptr || f.IsExcluded(static_cast<int>(i))) {
      f.map_point_ids[i] = -1;
      continue;
    }
    optim::PoseObservation o;
    o.X_w = p->X_w;
    o.uv = {f.keys_un[i].pt.x, f.keys_un[i].pt.y};
    o.u_right = f.u_right[i];
    o.inv_sigma2 = f.pyramid.inv_sigma2[f.keys_un[i].octave];
    o.weight = f.Weight(static_cast<int>(i));
    if (trace_.full_enabled()) {
      o.obs_id = "mp" + std::to_string(id) + "@f" + std::to_string(f.index);
      o.trace_feature = static_cast<int64_t>(i);  // link record (optim.h): the verifier's way to the OBS
    }
    obs.push_back(std::move(o));
    idx->push_back(static_cast<int>(i));
  }
  return obs;
}

int Tracker::OptimizePose(Frame& f) {
  if (current_frame_ != f.index) {
    current_frame_ = f.index;
    pose_call_ = 0;
  }
  ++pose_call_;
  const Intrinsics K = camera_.Pinhole();
  std::vector<int> idx;
  const std::vector<optim::PoseObservation> obs = PoseObservations(f, &idx);
  std::fill(f.outlier.begin(), f.outlier.end(), 0);
  const std::string name = "track.pose#" + std::to_string(pose_call_);
  if (structure_ != nullptr) {
    // Lines and planes re-associated at the current estimate join the same problem (issue 13).
    structure_->Associate(f, map_);
    std::vector<int> line_index, plane_index;
    const optim::PoseStructure ps = structure_->BuildPoseStructure(f, map_, &line_index, &plane_index);
    if (obs.size() + ps.lines.size() + ps.planes.size() < 3) return 0;
    const optim::PoseOnlyResult r = optim::OptimizePose(K, f.T_cw, obs, &ps, options_.pose, &trace_, name);
    f.T_cw = r.T_cw;
    for (size_t k = 0; k < idx.size(); ++k) f.outlier[idx[k]] = r.inlier[k] ? 0 : 1;
    structure_->ApplyPoseResult(f, r, line_index, plane_index);
    return r.num_inliers;
  }
  if (obs.size() < 3) return 0;
  const optim::PoseOnlyResult r = optim::OptimizePose(K, f.T_cw, obs, options_.pose, &trace_, name);
  f.T_cw = r.T_cw;
  for (size_t k = 0; k < idx.size(); ++k) f.outlier[idx[k]] = r.inlier[k] ? 0 : 1;
  return r.num_inliers;
}

int Tracker::DiscardOutliers(Frame& f) {
  int n_map = 0;
  for (size_t i = 0; i < f.N(); ++i) {
    const int64_t id = f.map_point_ids[i];
    if (id < 0) continue;
    MapPoint* p = map_.mp(id);
    if (f.outlier[i]) {
      f.map_point_ids[i] = -1;
      f.outlier[i] = 0;
      if (p != nullptr) p->last_seen_frame = f.index;
    } else if (p != nullptr && !p->bad && p->n_obs > 0) {
      ++n_map;
    }
  }
  if (structure_ != nullptr) {
    structure_->DiscardOutliers(f);
    n_map += StructureCount(structure_->InlierCount(f));
  }
  return n_map;
}

}  // namespace dynref::tracking
