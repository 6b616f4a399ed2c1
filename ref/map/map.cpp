// Map bookkeeping as ORB-SLAM2 MapPoint / KeyFrame / Map, with id-keyed containers.
#include "map/map.h"

#include <algorithm>
#include <limits>
#include <cmath>

#include "core/stable_sort.h"
#include "features/orb_extractor.h"

namespace dynref {

const char* LandmarkTypeName(LandmarkType t) {
  switch (t) {
    case LandmarkType::kPoint: return "point";
    case LandmarkType::kLine: return "line";
    case LandmarkType::kPlane: return "plane";
  }
  return "?";
}

const char* LandmarkEventName(LandmarkEvent::Kind k) {
  switch (k) {
    case LandmarkEvent::Kind::kCreated: return "created";
    case LandmarkEvent::Kind::kReplaced: return "replaced";
    case LandmarkEvent::Kind::kCulled: return "culled";
  }
  return "?";
}

int MapPoint::PredictScale(float distance, const ScalePyramid& pyr) const {
  // ORB-SLAM2 MapPoint::PredictScale.
  const float ratio = max_distance / distance;
  int n_scale = static_cast<int>(std::ceil(std::log(ratio) / std::log(static_cast<float>(pyr.scale_factor))));
  if (n_scale < 0) n_scale = 0;
  if (n_scale >= pyr.n_levels) n_scale = pyr.n_levels - 1;
  return n_scale;
}

std::vector<int64_t> KeyFrame::BestCovisibles(int n) const {
  if (static_cast<int>(ordered_covisibles.size()) <= n) return ordered_covisibles;
  return std::vector<int64_t>(ordered_covisibles.begin(), ordered_covisibles.begin() + n);
}

std::vector<int64_t> KeyFrame::CovisiblesWithWeight(int w) const {
  std::vector<int64_t> out;
  for (int64_t id : ordered_covisibles) {
    auto it = connections.find(id);
    if (it != connections.end() && it->second >= w) out.push_back(id);
  }
  return out;
}

int KeyFrame::TrackedMapPoints(int min_obs, const Map& map) const {
  int n = 0;
  for (int64_t id : map_point_ids) {
    if (id < 0) continue;
    const MapPoint* p = map.good_mp(id);
    if (p == nullptr) continue;
    if (min_obs > 0 ? p->n_obs >= min_obs : true) ++n;
  }
  return n;
}

double KeyFrame::SceneMedianDepth(const Map& map) const {
  std::vector<double> depths;
  for (int64_t id : map_point_ids) {
    const MapPoint* p = id >= 0 ? map.good_mp(id) : nullptr;
    if (p != nullptr) depths.push_back((T_cw * p->X_w).z());
  }
  if (depths.empty()) return -1;
  std::sort(depths.begin(), depths.end());
  return depths[(depths.size() - 1) / 2];
}

KeyFrame* Map::AddKeyFrame(std::unique_ptr<KeyFrame> kf) {
  kf->id = next_kf_id_++;
  KeyFrame* raw = kf.get();
  keyframes[raw->id] = std::move(kf);
  kf_by_id_.push_back(raw);  // id == kf_by_id_.size() - 1
  return raw;
}

MapPoint* Map::NewMapPoint(const Eigen::Vector3d& X_w, int64_t ref_kf, int frame_index) {
  auto p = std::make_unique<MapPoint>();
  p->id = next_mp_id_++;
  p->X_w = X_w;
  p->ref_kf = ref_kf;
  p->first_kf = ref_kf;
  p->first_frame = frame_index;
  MapPoint* raw = p.get();
  points[raw->id] = std::move(p);
  mp_by_id_.push_back(raw);  // id == mp_by_id_.size() - 1
  Notify(LandmarkEvent::Kind::kCreated, raw->id);
  return raw;
}

size_t Map::GoodPointCount() const {
  size_t n = 0;
  for (const auto& kv : points) n += kv.second->bad ? 0 : 1;
  return n;
}

SE3 Map::ResolvedT_cw(int64_t kf_id) const {
  SE3 T = SE3::Identity();
  const KeyFrame* k = kf(kf_id);
  int guard = 0;
  while (k != nullptr && k->bad && guard++ < 100000) {
    T = T * k->T_cp;
    k = kf(k->parent);
  }
  return k != nullptr ? T * k->T_cw : T;
}

void Map::AddObservation(int64_t mp_id, int64_t kf_id, int idx) {
  MapPoint* p = mp(mp_id);
  KeyFrame* k = kf(kf_id);
  if (p == nullptr || k == nullptr) return;
  if (p->observations.count(kf_id)) return;
  p->observations[kf_id] = idx;
  p->n_obs += k->frame.u_right[idx] >= 0 ? 2 : 1;
  k->map_point_ids[idx] = mp_id;
}

void Map::EraseObservation(int64_t mp_id, int64_t kf_id) {
  MapPoint* p = mp(mp_id);
  KeyFrame* k = kf(kf_id);
  if (p == nullptr || k == nullptr) return;
  auto it = p->observations.find(kf_id);
  if (it == p->observations.end()) return;
  const int idx = it->second;
  p->n_obs -= k->frame.u_right[idx] >= 0 ? 2 : 1;
  p->observations.erase(it);
  if (k->map_point_ids[idx] == mp_id) k->map_point_ids[idx] = -1;
  if (p->ref_kf == kf_id && !p->observations.empty()) p->ref_kf = p->observations.begin()->first;
  // ORB-SLAM2: a point seen by <= 2 (counted) observations is removed.
  if (p->n_obs <= 2) SetBadPoint(mp_id);
}

void Map::SetBadPoint(int64_t mp_id) {
  MapPoint* p = mp(mp_id);
  if (p == nullptr || p->bad) return;
  p->bad = true;
  for (const auto& [kf_id, idx] : p->observations) {
    KeyFrame* k = kf(kf_id);
    if (k != nullptr && k->map_point_ids[idx] == mp_id) k->map_point_ids[idx] = -1;
  }
  p->observations.clear();
  p->n_obs = 0;
  Notify(LandmarkEvent::Kind::kCulled, mp_id);
}

void Map::ReplacePoint(int64_t mp_id, int64_t by_id) {
  // ORB-SLAM2 MapPoint::Replace.
  if (mp_id == by_id) return;
  MapPoint* p = mp(mp_id);
  MapPoint* by = mp(by_id);
  if (p == nullptr || by == nullptr || p->bad) return;
  const std::map<int64_t, int> obs = p->observations;
  p->observations.clear();
  p->n_obs = 0;
  p->bad = true;
  p->replaced_by = by_id;
  for (const auto& [kf_id, idx] : obs) {
    KeyFrame* k = kf(kf_id);
    if (k == nullptr) continue;
    if (!by->observations.count(kf_id)) {
      k->map_point_ids[idx] = -1;
      AddObservation(by_id, kf_id, idx);
    } else if (k->map_point_ids[idx] == mp_id) {
      k->map_point_ids[idx] = -1;
    }
  }
  by->found += p->found;
  by->visible += p->visible;
  UpdatePointDescriptor(by_id);
  Notify(LandmarkEvent::Kind::kReplaced, mp_id, by_id);
}

void Map::RemoveObserver(LandmarkObserver* observer) {
  observers_.erase(std::remove(observers_.begin(), observers_.end(), observer), observers_.end());
}

void Map::Notify(LandmarkEvent::Kind kind, int64_t mp_id, int64_t by_id) {
  NotifyTyped(kind, LandmarkType::kPoint, mp_id, by_id);
}

void Map::NotifyTyped(LandmarkEvent::Kind kind, LandmarkType type, int64_t id, int64_t by_id) {
  if (observers_.empty()) return;
  LandmarkEvent e;
  e.kind = kind;
  e.landmark = {type, id};
  e.by_id = by_id;
  for (LandmarkObserver* o : observers_) o->OnLandmarkEvent(e);
}

void Map::SetBadKeyFrame(int64_t kf_id) {
  // ORB-SLAM2 KeyFrame::SetBadFlag (the spanning tree is re-linked to the parent; no loop edges).
  KeyFrame* k = kf(kf_id);
  if (k == nullptr || k->bad || kf_id == 0 || k->not_erase) return;
  for (const auto& [other_id, w] : k->connections) {
    (void)w;
    KeyFrame* o = kf(other_id);
    if (o == nullptr) continue;
    o->connections.erase(kf_id);
    o->ordered_covisibles.erase(std::remove(o->ordered_covisibles.begin(), o->ordered_covisibles.end(), kf_id),
                                o->ordered_covisibles.end());
  }
  for (size_t i = 0; i < k->map_point_ids.size(); ++i) {
    const int64_t id = k->map_point_ids[i];
    if (id >= 0) EraseObservation(id, kf_id);
  }
  // Live children move to this keyframe's parent; culled ones keep their parent, because their
  // T_cp is relative to it (ORB-SLAM2 erases a culled keyframe from its parent's children).
  for (auto& kv : keyframes)
    if (kv.second->parent == kf_id && !kv.second->bad) kv.second->parent = k->parent;
  const KeyFrame* parent = kf(k->parent);
  if (parent != nullptr) k->T_cp = k->T_cw * parent->T_cw.inverse();
  EraseStructureObservations(*k);
  k->connections.clear();
  k->ordered_covisibles.clear();
  k->bad = true;
  // A culled keyframe is never a stage's reference again: release its images (memory).
  k->frame.rgb.release();
  k->frame.grey.release();
  k->frame.depth_m.release();
}

void Map::UpdatePointDescriptor(int64_t mp_id) {
  // ORB-SLAM2 MapPoint::ComputeDistinctiveDescriptors: the descriptor with the least median
  // distance to all others.
  MapPoint* p = mp(mp_id);
  if (p == nullptr || p->bad) return;
  std::vector<std::pair<const cv::Mat*, int>> descs;  // (descriptor matrix, row)
  for (const auto& [kf_id, idx] : p->observations) {
    const KeyFrame* k = kf(kf_id);
    if (k != nullptr && !k->bad) descs.emplace_back(&k->frame.descriptors, idx);
  }
  if (descs.empty()) return;
  const size_t n = descs.size();
  std::vector<std::vector<float>> d(n, std::vector<float>(n, 0));
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      d[i][j] = d[j][i] = features::RowDistance(*descs[i].first, descs[i].second, *descs[j].first, descs[j].second);
  float best_median = std::numeric_limits<float>::infinity();
  size_t best = 0;
  for (size_t i = 0; i < n; ++i) {
    std::vector<float> row = d[i];
    std::sort(row.begin(), row.end());
    const float median = row[static_cast<size_t>(0.5 * (n - 1))];
    if (median < best_median) {
      best_median = median;
      best = i;
    }
  }
  p->descriptor = descs[best].first->row(descs[best].second).clone();
}

void Map::UpdatePointNormalAndDepth(int64_t mp_id) {
  // ORB-SLAM2 MapPoint::UpdateNormalAndDepth.
  MapPoint* p = mp(mp_id);
  if (p == nullptr || p->bad || p->observations.empty()) return;
  const KeyFrame* ref = kf(p->ref_kf);
  if (ref == nullptr) return;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  int n = 0;
  for (const auto& [kf_id, idx] : p->observations) {
    (void)idx;
    const KeyFrame* k = kf(kf_id);
    if (k == nullptr) continue;
    const Eigen::Vector3d v = p->X_w - k->CameraCentre();
    normal += v / v.norm();
    ++n;
  }
  auto it = p->observations.find(p->ref_kf);
  if (it == p->observations.end() || n == 0) return;
  const double dist = (p->X_w - ref->CameraCentre()).norm();
  const int level = ref->frame.keys_un[it->second].octave;
  const ScalePyramid& pyr = ref->frame.pyramid;
  p->max_distance = static_cast<float>(dist * pyr.scale[level]);
  p->min_distance = p->max_distance / pyr.scale[pyr.n_levels - 1];
  p->normal = normal / n;
}

void Map::UpdateConnections(int64_t kf_id) {
  // ORB-SLAM2 KeyFrame::UpdateConnections (threshold 15 shared points).
  KeyFrame* k = kf(kf_id);
  if (k == nullptr || k->bad) return;
  std::map<int64_t, int> counter;
  for (int64_t id : k->map_point_ids) {
    const MapPoint* p = id >= 0 ? good_mp(id) : nullptr;
    if (p == nullptr) continue;
    for (const auto& [other, idx] : p->observations) {
      (void)idx;
      if (other == kf_id) continue;
      const KeyFrame* o = kf(other);
      if (o == nullptr || o->bad) continue;
      counter[other]++;
    }
  }
  if (counter.empty()) return;
  int n_max = 0;
  int64_t kf_max = -1;
  const int th = 15;
  for (const auto& [other, w] : counter) {
    if (w > n_max) {
      n_max = w;
      kf_max = other;
    }
  }
  for (const auto& [other, w] : counter) {
    if (w >= th || other == kf_max) {
      KeyFrame* o = kf(other);
      o->connections[kf_id] = w;
      std::vector<int64_t> ids;
      for (const auto& kv : o->connections) ids.push_back(kv.first);
      StableSortBy(ids, [&](int64_t id) { return -o->connections.at(id); });
      o->ordered_covisibles = ids;
    }
  }
  k->connections = counter;
  std::vector<int64_t> ordered;
  for (const auto& [other, w] : counter)
    if (w >= th || other == kf_max) ordered.push_back(other);
  StableSortBy(ordered, [&](int64_t id) { return -counter.at(id); });
  k->ordered_covisibles = ordered;
  if (k->parent < 0 && kf_id != 0 && !ordered.empty()) k->parent = ordered.front();
}

}  // namespace dynref
