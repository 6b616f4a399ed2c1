// Where keyframes come from: map initialisation (ORB-SLAM2 Tracking::StereoInitialization) and
// the keyframe decision and insertion (NeedNewKeyFrame, CreateNewKeyFrame); see tracker.h.
#include <algorithm>
#include <memory>
#include <utility>

#include "tracking/tracker.h"

namespace dynref::tracking {
namespace {

// A keyframe snapshot of a tracked frame: pose, associations and the rgb/depth images the
// method stages read; no grey image, no detections or trace pointers (they die with the frame).
std::unique_ptr<KeyFrame> TrackerKeyFrameSnapshot(const Frame& f) {
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

KeyFrame* Tracker::AddKeyFrameOf(const Frame& f) {
  KeyFrame* k = map_.AddKeyFrame(TrackerKeyFrameSnapshot(f));
  TraceKeyFrame(*k);
  return k;
}

// A new map point at feature i's depth, observed by keyframe k (made from f).
void Tracker::AddPointFromDepth(Frame& f, const KeyFrame& k, int i) {
  MapPoint* p = map_.NewMapPoint(f.UnprojectWorld(i), k.id, f.index);
  map_.AddObservation(p->id, k.id, i);
  map_.UpdatePointDescriptor(p->id);
  map_.UpdatePointNormalAndDepth(p->id);
  f.map_point_ids[i] = p->id;
}

KeyFrame* Tracker::TryInitialise(Frame& f) {
  int n = 0;
  for (size_t i = 0; i < f.N(); ++i) n += (f.depth[i] > 0 && !f.IsExcluded(static_cast<int>(i))) ? 1 : 0;
  trace_.FrameCount("track.init", "features_with_depth", n);
  if (n <= options_.min_init_points) return nullptr;
  f.T_cw = SE3::Identity();
  f.has_pose = true;
  std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  KeyFrame* k = AddKeyFrameOf(f);
  for (size_t i = 0; i < f.N(); ++i) {
    if (!(f.depth[i] > 0) || f.IsExcluded(static_cast<int>(i))) continue;
    AddPointFromDepth(f, *k, static_cast<int>(i));
  }
  if (structure_ != nullptr) structure_->CreateLandmarks(f, *k, map_);
  reference_kf_ = k->id;
  last_kf_frame_ = f.index;
  local_kfs_ = {k->id};
  has_velocity_ = false;
  state_ = TrackState::kOk;
  return k;
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
  KeyFrame* k = AddKeyFrameOf(f);
  reference_kf_ = k->id;
  const int n_new = AddPointsByDepth(f, *k);
  last_kf_frame_ = f.index;
  trace_.FrameCount("track.keyframe", "new_points", n_new);
  if (structure_ != nullptr) structure_->CreateLandmarks(f, *k, map_);
  return k;
}

// New map points from depth, closest first, until 100 beyond the close threshold (ORB-SLAM2
// Tracking::CreateNewKeyFrame); a feature keeps a good point it already has. Returns the count.
int Tracker::AddPointsByDepth(Frame& f, KeyFrame& k) {
  std::vector<std::pair<float, int>> by_depth;
  for (size_t i = 0; i < f.N(); ++i)
    if (f.depth[i] > 0 && !f.IsExcluded(static_cast<int>(i))) by_depth.emplace_back(f.depth[i], static_cast<int>(i));
  std::sort(by_depth.begin(), by_depth.end());
  const double th_depth_m = camera_.th_depth * camera_.baseline_m();
  int n_points = 0, n_new = 0;
  for (const auto& [d, i] : by_depth) {
    bool create = false;
    const int64_t id = k.map_point_ids[i];
    if (id < 0) {
      create = true;
    } else {
      const MapPoint* p = map_.good_mp(id);
      if (p == nullptr || p->n_obs < 1) {
        create = true;
        k.map_point_ids[i] = -1;
        f.map_point_ids[i] = -1;
      }
    }
    if (create) {
      AddPointFromDepth(f, k, i);
      ++n_new;
    }
    ++n_points;
    if (d > th_depth_m && n_points > 100) break;
  }
  return n_new;
}

}  // namespace dynref::tracking
