// ORB-SLAM2 Tracking (src/Tracking.cc, RGB-D branch) as explicit steps; see tracker.h.
#include "tracking/tracker.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "optim/optim.h"
#include "tracking/matcher.h"
#include "tracking/relocaliser_bow.h"

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

namespace {

// A keyframe snapshot of a tracked frame: pose, associations and the rgb/depth images the
// method stages read; no grey image, no detections or trace pointers (they die with the frame).
std::unique_ptr<KeyFrame> KeyFrameFromFrame(const Frame& f) {
  auto kf = std::make_unique<KeyFrame>();
  kf->frame = f;
  kf->frame.detections = nullptr;
  kf->frame.trace = nullptr;
  kf->frame.grey.release();
  kf->frame_index = f.index;
  kf->stamp = f.stamp;
  kf->stamp_text = f.stamp_text;
  kf->T_cw = f.T_cw;
  kf->map_point_ids = f.map_point_ids;
  return kf;
}

}  // namespace

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

int Tracker::OptimizePose(Frame& f) {
  if (current_frame_ != f.index) {
    current_frame_ = f.index;
    pose_call_ = 0;
  }
  ++pose_call_;
  const Intrinsics K = camera_.Pinhole();
  std::vector<optim::PoseObservation> obs;
  std::vector<int> idx;
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
    idx.push_back(static_cast<int>(i));
  }
  std::fill(f.outlier.begin(), f.outlier.end(), 0);
  if (structure_ != nullptr) {
    // Lines and planes re-associated at the current estimate join the same problem (issue 13).
    structure_->Associate(f, map_);
    std::vector<int> line_index, plane_index;
    const optim::PoseStructure ps = structure_->BuildPoseStructure(f, map_, &line_index, &plane_index);
    if (obs.size() + ps.lines.size() + ps.planes.size() < 3) return 0;
    const optim::PoseOnlyResult r = optim::OptimizePose(K, f.T_cw, obs, &ps, options_.pose, &trace_,
                                                        "track.pose#" + std::to_string(pose_call_));
    f.T_cw = r.T_cw;
    for (size_t k = 0; k < idx.size(); ++k) f.outlier[idx[k]] = r.inlier[k] ? 0 : 1;
    structure_->ApplyPoseResult(f, r, line_index, plane_index);
    return r.num_inliers;
  }
  if (obs.size() < 3) return 0;
  const optim::PoseOnlyResult r = optim::OptimizePose(K, f.T_cw, obs, options_.pose, &trace_,
                                                      "track.pose#" + std::to_string(pose_call_));
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

void Tracker::UpdateLocalKeyFrames(Frame& f) {
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
  auto add = [&](int64_t id) {
    KeyFrame* k = map_.kf(id);
    if (k == nullptr || k->bad || k->track_ref_frame == f.index) return false;
    k->track_ref_frame = f.index;
    local_kfs_.push_back(id);
    return true;
  };
  // ORB-SLAM2 Tracking::UpdateLocalKeyFrames expands only the keyframes that observe a matched
  // point (its loop end is fixed before the neighbours are appended), and adding a parent ends
  // the expansion (the break there leaves the outer loop).
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
  if (kf_max >= 0) reference_kf_ = kf_max;
}

void Tracker::SearchLocalMap(Frame& f) {
  UpdateLocalKeyFrames(f);
  std::vector<int64_t> local_points;
  for (int64_t kf_id : local_kfs_) {
    const KeyFrame* k = map_.kf(kf_id);
    for (int64_t id : k->map_point_ids) {
      if (id < 0) continue;
      MapPoint* p = map_.good_mp(id);
      if (p == nullptr || p->track_ref_frame == f.index) continue;
      p->track_ref_frame = f.index;
      local_points.push_back(id);
    }
  }
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

bool Tracker::NeedNewKeyFrame(const Frame& f, bool mapping_idle, int keyframes_queued,
                              int max_queue) const {
  // ORB-SLAM2 Tracking::NeedNewKeyFrame (RGB-D).
  int n_kfs = 0;
  for (const auto& kv : map_.keyframes) n_kfs += kv.second->bad ? 0 : 1;
  if (f.index < last_reloc_frame_ + options_.max_frames && n_kfs > options_.max_frames) return false;
  const int min_obs = n_kfs <= 2 ? 2 : 3;
  const KeyFrame* ref = map_.kf(reference_kf_);
  const int ref_matches = ref != nullptr ? ref->TrackedMapPoints(min_obs, map_) : 0;
  const double th_depth_m = camera_.th_depth * camera_.baseline_m();
  int tracked_close = 0, non_tracked_close = 0;
  for (size_t i = 0; i < f.N(); ++i) {
    if (f.IsExcluded(static_cast<int>(i))) continue;
    if (f.depth[i] > 0 && f.depth[i] < th_depth_m) {
      if (f.map_point_ids[i] >= 0 && !f.outlier[i]) ++tracked_close;
      else ++non_tracked_close;
    }
  }
  const bool need_close = tracked_close < 100 && non_tracked_close > 70;
  const double th_ref_ratio = n_kfs < 2 ? 0.4 : 0.75;
  const bool c1a = f.index >= last_kf_frame_ + options_.max_frames;
  const bool c1b = f.index >= last_kf_frame_ + options_.min_frames && mapping_idle;
  const bool c1c = matches_inliers_ < ref_matches * 0.25 || need_close;
  const bool c2 = (matches_inliers_ < ref_matches * th_ref_ratio || need_close) &&
                  matches_inliers_ + structure_inliers_ > 15;
  if (!((c1a || c1b || c1c) && c2)) return false;
  // Busy mapping: ORB-SLAM2 interrupts local BA and, for RGB-D, inserts while the queue is short.
  return mapping_idle || keyframes_queued < max_queue;
}

KeyFrame* Tracker::CreateNewKeyFrame(Frame& f) {
  // Outlier associations are dropped before the keyframe is made (ORB-SLAM2 keeps them in the
  // keyframe until local mapping; dropping them is the cleaner equivalent).
  for (size_t i = 0; i < f.N(); ++i)
    if (f.outlier[i]) f.DropAssociation(static_cast<int>(i));  // OBS keeps it as associated
  // No parent here: ORB-SLAM2 sets the spanning-tree parent in KeyFrame::UpdateConnections (its
  // first connection: the keyframe sharing most points), run by local mapping.
  KeyFrame* k = map_.AddKeyFrame(KeyFrameFromFrame(f));
  TraceKeyFrame(*k);
  reference_kf_ = k->id;
  // New map points from depth, closest first, until 100 beyond the close threshold (ORB-SLAM2
  // Tracking::CreateNewKeyFrame).
  std::vector<std::pair<float, int>> by_depth;
  for (size_t i = 0; i < f.N(); ++i)
    if (f.depth[i] > 0 && !f.IsExcluded(static_cast<int>(i))) by_depth.emplace_back(f.depth[i], static_cast<int>(i));
  std::sort(by_depth.begin(), by_depth.end());
  const double th_depth_m = camera_.th_depth * camera_.baseline_m();
  int n_points = 0, n_new = 0;
  for (const auto& [d, i] : by_depth) {
    bool create = false;
    const int64_t id = k->map_point_ids[i];
    if (id < 0) {
      create = true;
    } else {
      const MapPoint* p = map_.good_mp(id);
      if (p == nullptr || p->n_obs < 1) {
        create = true;
        k->map_point_ids[i] = -1;
        f.map_point_ids[i] = -1;
      }
    }
    if (create) {
      MapPoint* p = map_.NewMapPoint(f.UnprojectWorld(i), k->id, f.index);
      map_.AddObservation(p->id, k->id, i);
      map_.UpdatePointDescriptor(p->id);
      map_.UpdatePointNormalAndDepth(p->id);
      f.map_point_ids[i] = p->id;
      ++n_new;
    }
    ++n_points;
    if (d > th_depth_m && n_points > 100) break;
  }
  last_kf_frame_ = f.index;
  trace_.FrameCount("track.keyframe", "new_points", n_new);
  if (structure_ != nullptr) structure_->CreateLandmarks(f, *k, map_);
  return k;
}

KeyFrame* Tracker::TryInitialise(Frame& f) {
  int n = 0;
  for (size_t i = 0; i < f.N(); ++i) n += (f.depth[i] > 0 && !f.IsExcluded(static_cast<int>(i))) ? 1 : 0;
  trace_.FrameCount("track.init", "features_with_depth", n);
  if (n <= options_.min_init_points) return nullptr;
  f.T_cw = SE3::Identity();
  f.has_pose = true;
  std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  KeyFrame* k = map_.AddKeyFrame(KeyFrameFromFrame(f));
  TraceKeyFrame(*k);
  for (size_t i = 0; i < f.N(); ++i) {
    if (!(f.depth[i] > 0) || f.IsExcluded(static_cast<int>(i))) continue;
    MapPoint* p = map_.NewMapPoint(f.UnprojectWorld(static_cast<int>(i)), k->id, f.index);
    map_.AddObservation(p->id, k->id, static_cast<int>(i));
    map_.UpdatePointDescriptor(p->id);
    map_.UpdatePointNormalAndDepth(p->id);
    f.map_point_ids[i] = p->id;
  }
  if (structure_ != nullptr) structure_->CreateLandmarks(f, *k, map_);
  reference_kf_ = k->id;
  last_kf_frame_ = f.index;
  local_kfs_ = {k->id};
  has_velocity_ = false;
  state_ = TrackState::kOk;
  return k;
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
