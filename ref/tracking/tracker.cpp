// ORB-SLAM2 Tracking (src/Tracking.cc, RGB-D branch) as explicit steps; see tracker.h. This
// file: options, the choice of initial-pose method per frame and the frame's end. The steps:
// pose_tracking.cpp (motion model, reference keyframe, pose optimisation), relocalise.cpp,
// local_map.cpp (local map search, final pose), new_keyframes.cpp (initialisation, keyframe
// decision and insertion).
#include "tracking/tracker.h"

#include <algorithm>

#include "core/error.h"

namespace dynref::tracking {

void TrackerOptions::Check() const {
  if (min_init_points < 1) throw InputError("tracker options", "min_init_points must be >= 1");
  if (max_frames < 1) throw InputError("tracker options", "max_frames must be >= 1");
  if (min_frames < 0) throw InputError("tracker options", "min_frames must be >= 0");
  if (reloc_recent_keyframes < 1) throw InputError("tracker options", "reloc_recent_keyframes must be >= 1");
  if (ransac_iterations < 1) throw InputError("tracker options", "ransac_iterations must be >= 1");
  if (relocalisation != "recent" && relocalisation != "bow")
    throw InputError("tracker options", "relocalisation must be recent or bow, got '" + relocalisation + "'");
  pose.Check();
}

const char* TrackStateName(TrackState s) {
  switch (s) {
    case TrackState::kNotInitialised: return "not_initialised";
    case TrackState::kOk: return "ok";
    case TrackState::kLost: return "lost";
  }
  return "?";
}

Tracker::Tracker(const Camera& camera, Map& map, const TrackerOptions& options, trace::TraceWriter& trace)
    : camera_(camera), map_(map), options_(options), trace_(trace), rng_(options.seed, "tracking.reloc") {
  options_.Check();
}

void Tracker::TraceKeyFrame(const KeyFrame& k) {
  // The keyframe -> frame link local-BA residuals "mp<N>@kf<k>" need (tracking/README.md "Trace").
  if (trace_.full_enabled())
    trace_.ProbabilityUpdate("track.keyframe", trace::EntityKind::kKeyFrame, "kf" + std::to_string(k.id),
                             {{"frame", static_cast<double>(k.frame_index)}}, 0.0, 0.0);
}

void Tracker::UpdateLastFramePose() {
  if (records_.empty() || records_.back().lost) return;
  const KeyFrame* ref = map_.kf(records_.back().ref_kf);
  if (ref != nullptr) last_.T_cw = records_.back().T_cr * ref->T_cw;
}

void Tracker::CheckReplacedInLastFrame() {
  if (!has_last_) return;
  for (int64_t& id : last_.map_point_ids) {
    if (id < 0) continue;
    int guard = 0;
    const MapPoint* p = map_.mp(id);
    while (p != nullptr && p->replaced_by >= 0 && guard++ < 100) {
      id = p->replaced_by;
      p = map_.mp(id);
    }
  }
}

bool Tracker::TrackInitial(Frame& f) {
  CheckReplacedInLastFrame();
  std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  bool ok = false;
  if (state_ == TrackState::kOk) {
    if (!has_velocity_ || f.index < last_reloc_frame_ + 2) {
      ok = TrackReferenceKeyFrame(f);
    } else {
      ok = TrackWithMotionModel(f);
      if (!ok) ok = TrackReferenceKeyFrame(f);
    }
  } else {
    ok = Relocalise(f);
  }
  if (!ok) std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  f.has_pose = ok;
  return ok;
}

void Tracker::FinishFrame(Frame& f, bool ok) {
  FrameRecord rec;
  rec.index = f.index;
  rec.stamp = f.stamp;
  rec.stamp_text = f.stamp_text;
  if (ok) {
    for (size_t i = 0; i < f.N(); ++i) {
      const int64_t id = f.map_point_ids[i];
      if (id < 0) continue;
      const MapPoint* p = map_.good_mp(id);
      if (p == nullptr || p->n_obs < 1 || f.outlier[i]) f.map_point_ids[i] = -1;
    }
    state_ = TrackState::kOk;
    f.has_pose = true;
    const KeyFrame* ref = map_.kf(reference_kf_);
    rec.ref_kf = reference_kf_;
    // ORB-SLAM2 Tracking::Track stores Tcw * Tref^-1 before local mapping processes a new
    // keyframe; for a keyframe made from this frame that is the identity, so the trajectory
    // follows the keyframe's optimised pose (local BA has already run when FinishFrame is called).
    rec.T_cr = ref->frame_index == f.index ? SE3::Identity() : f.T_cw * ref->T_cw.inverse();
    rec.lost = false;
  } else {
    if (state_ != TrackState::kNotInitialised) state_ = TrackState::kLost;
    f.has_pose = false;
    if (!records_.empty()) {
      rec.ref_kf = records_.back().ref_kf;
      rec.T_cr = records_.back().T_cr;
    }
    rec.lost = true;
  }
  records_.push_back(rec);
  last_ = f;
  last_.detections = nullptr;
  last_.trace = nullptr;
  has_last_ = true;
}

}  // namespace dynref::tracking
