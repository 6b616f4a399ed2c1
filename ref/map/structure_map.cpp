// Map bookkeeping of line and plane landmarks (issue 13); see map/structure.h.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "map/map.h"

namespace dynref {

void FrameStructure::Reset(size_t n_lines, size_t n_planes) {
  map_line_ids.assign(n_lines, -1);
  line_outlier.assign(n_lines, 0);
  line_weight.assign(n_lines, 1.0);
  map_plane_ids.assign(n_planes, -1);
  plane_outlier.assign(n_planes, 0);
}

MapLine* Map::NewMapLine(const Eigen::Vector3d& P_s, const Eigen::Vector3d& P_e, const cv::Mat& descriptor,
                         int64_t kf_id, int frame_index) {
  auto l = std::make_unique<MapLine>();
  l->id = next_line_id_++;
  l->P_s = P_s;
  l->P_e = P_e;
  l->descriptor = descriptor.clone();
  l->first_kf = kf_id;
  l->first_frame = frame_index;
  MapLine* raw = l.get();
  lines[raw->id] = std::move(l);
  NotifyTyped(LandmarkEvent::Kind::kCreated, LandmarkType::kLine, raw->id);
  return raw;
}

MapPlane* Map::NewMapPlane(const Eigen::Vector3d& n_w, double d_w, int64_t kf_id, int frame_index) {
  if (!(n_w.norm() > 1e-9) || !std::isfinite(d_w))
    throw std::invalid_argument("NewMapPlane: zero or non-finite normal / distance");
  auto p = std::make_unique<MapPlane>();
  p->id = next_plane_id_++;
  p->n = n_w.normalized();
  p->d = d_w;
  p->first_kf = kf_id;
  p->first_frame = frame_index;
  MapPlane* raw = p.get();
  planes[raw->id] = std::move(p);
  NotifyTyped(LandmarkEvent::Kind::kCreated, LandmarkType::kPlane, raw->id);
  return raw;
}

MapLine* Map::good_line(int64_t id) {
  auto it = lines.find(id);
  return it == lines.end() || it->second->bad ? nullptr : it->second.get();
}
const MapLine* Map::good_line(int64_t id) const {
  auto it = lines.find(id);
  return it == lines.end() || it->second->bad ? nullptr : it->second.get();
}
MapPlane* Map::good_plane(int64_t id) {
  auto it = planes.find(id);
  return it == planes.end() || it->second->bad ? nullptr : it->second.get();
}
const MapPlane* Map::good_plane(int64_t id) const {
  auto it = planes.find(id);
  return it == planes.end() || it->second->bad ? nullptr : it->second.get();
}

void Map::AddLineObservation(int64_t line_id, int64_t kf_id, int idx) {
  MapLine* l = good_line(line_id);
  KeyFrame* k = kf(kf_id);
  if (l == nullptr || k == nullptr || l->observations.count(kf_id)) return;
  l->observations[kf_id] = idx;
  k->frame.structure.map_line_ids[static_cast<size_t>(idx)] = line_id;
}

void Map::AddPlaneObservation(int64_t plane_id, int64_t kf_id, int idx) {
  MapPlane* p = good_plane(plane_id);
  KeyFrame* k = kf(kf_id);
  if (p == nullptr || k == nullptr || p->observations.count(kf_id)) return;
  p->observations[kf_id] = idx;
  k->frame.structure.map_plane_ids[static_cast<size_t>(idx)] = plane_id;
}

void Map::SetBadLine(int64_t line_id) {
  MapLine* l = good_line(line_id);
  if (l == nullptr) return;
  l->bad = true;
  for (const auto& [kf_id, idx] : l->observations) {
    KeyFrame* k = kf(kf_id);
    if (k != nullptr && k->frame.structure.map_line_ids[static_cast<size_t>(idx)] == line_id)
      k->frame.structure.map_line_ids[static_cast<size_t>(idx)] = -1;
  }
  l->observations.clear();
  NotifyTyped(LandmarkEvent::Kind::kCulled, LandmarkType::kLine, line_id);
}

void Map::ReplacePlane(int64_t plane_id, int64_t by_id) {
  if (plane_id == by_id) return;
  MapPlane* p = good_plane(plane_id);
  MapPlane* by = good_plane(by_id);
  if (p == nullptr || by == nullptr) return;
  const std::map<int64_t, int> obs = p->observations;
  p->observations.clear();
  p->bad = true;
  p->replaced_by = by_id;
  for (const auto& [kf_id, idx] : obs) {
    KeyFrame* k = kf(kf_id);
    if (k == nullptr) continue;
    k->frame.structure.map_plane_ids[static_cast<size_t>(idx)] = -1;
    AddPlaneObservation(by_id, kf_id, idx);  // a keyframe that sees both keeps its own of by_id
  }
  by->found += p->found;
  by->visible += p->visible;
  NotifyTyped(LandmarkEvent::Kind::kReplaced, LandmarkType::kPlane, plane_id, by_id);
}

void Map::EraseStructureObservations(KeyFrame& k) {
  FrameStructure& s = k.frame.structure;
  for (size_t i = 0; i < s.map_line_ids.size(); ++i) {
    MapLine* l = s.map_line_ids[i] >= 0 ? good_line(s.map_line_ids[i]) : nullptr;
    if (l == nullptr) continue;
    l->observations.erase(k.id);
    if (l->observations.empty()) SetBadLine(l->id);
  }
  for (size_t i = 0; i < s.map_plane_ids.size(); ++i) {
    MapPlane* p = s.map_plane_ids[i] >= 0 ? good_plane(s.map_plane_ids[i]) : nullptr;
    if (p == nullptr) continue;
    p->observations.erase(k.id);
    if (p->observations.empty()) {
      p->bad = true;
      NotifyTyped(LandmarkEvent::Kind::kCulled, LandmarkType::kPlane, p->id);
    }
  }
}

size_t Map::GoodLineCount() const {
  return static_cast<size_t>(std::count_if(lines.begin(), lines.end(), [](const auto& kv) { return !kv.second->bad; }));
}
size_t Map::GoodPlaneCount() const {
  return static_cast<size_t>(std::count_if(planes.begin(), planes.end(), [](const auto& kv) { return !kv.second->bad; }));
}

}  // namespace dynref
