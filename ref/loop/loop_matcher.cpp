// ORBmatcher searches of loop closing; see loop_matcher.h.
#include "loop/loop_matcher.h"

#include <cmath>
#include <set>

#include "features/descriptor.h"

namespace dynref::loop {
namespace {

// A projected point's search window in kf (the tests shared by SearchByProjection and Fuse).
struct Window {
  double u = 0, v = 0, radius = 0;
  int level = 0;
};

bool Project(const KeyFrame& kf, const SE3& T_cw, const MapPoint& p, float th, Window* w) {
  const Frame& f = kf.frame;
  const Eigen::Vector3d X_c = T_cw * p.X_w;
  if (X_c.z() <= 0) return false;
  const Camera& cam = *f.camera;
  w->u = cam.fx * X_c.x() / X_c.z() + cam.cx;
  w->v = cam.fy * X_c.y() / X_c.z() + cam.cy;
  if (w->u < f.min_x || w->u > f.max_x || w->v < f.min_y || w->v > f.max_y) return false;
  const Eigen::Vector3d O_w = T_cw.inverse().translation();
  const Eigen::Vector3d PO = p.X_w - O_w;
  const double dist = PO.norm();
  if (dist < 0.8 * p.min_distance || dist > 1.2 * p.max_distance) return false;
  if (PO.dot(p.normal) < 0.5 * dist) return false;  // viewing angle > 60 deg
  w->level = p.PredictScale(static_cast<float>(dist), f.pyramid);
  w->radius = th * f.pyramid.scale[w->level];
  return true;
}

}  // namespace

std::vector<int64_t> SearchByBoWKeyFrames(const KeyFrame& kf1, const tracking::PlaceBow& bow1, const KeyFrame& kf2,
                                          const tracking::PlaceBow& bow2, const Map& map, float ratio) {
  std::vector<int64_t> out(kf1.N(), -1);
  std::vector<int> used2(kf2.N(), 0);
  std::vector<std::vector<int>> hist(features::kHistoLength);
  const Frame& f1 = kf1.frame;
  const Frame& f2 = kf2.frame;
  const bool orient = f1.match_profile.oriented;
  const float worst = f1.match_profile.worst;
  auto it1 = bow1.features.begin();
  auto it2 = bow2.features.begin();
  while (it1 != bow1.features.end() && it2 != bow2.features.end()) {
    if (it1->first < it2->first) {
      it1 = bow1.features.lower_bound(it2->first);
      continue;
    }
    if (it2->first < it1->first) {
      it2 = bow2.features.lower_bound(it1->first);
      continue;
    }
    for (uint32_t i1 : it1->second) {
      const int64_t mp1 = kf1.map_point_ids[i1];
      if (mp1 < 0 || map.good_mp(mp1) == nullptr || f1.IsExcluded(static_cast<int>(i1))) continue;
      float best1 = worst, best2 = worst;
      int best_idx = -1;
      for (uint32_t i2 : it2->second) {
        const int64_t mp2 = kf2.map_point_ids[i2];
        if (used2[i2] || mp2 < 0 || map.good_mp(mp2) == nullptr || f2.IsExcluded(static_cast<int>(i2))) continue;
        const float d = features::RowDistance(f1.descriptors, static_cast<int>(i1), f2.descriptors, static_cast<int>(i2));
        if (d < best1) {
          best2 = best1;
          best1 = d;
          best_idx = static_cast<int>(i2);
        } else if (d < best2) {
          best2 = d;
        }
      }
      if (best_idx >= 0 && best1 < f1.match_profile.th_low && best1 < ratio * best2) {
        out[i1] = kf2.map_point_ids[best_idx];
        used2[best_idx] = 1;
        if (orient) hist[features::RotationBin(f1.keys_un[i1].angle, f2.keys_un[best_idx].angle)].push_back(static_cast<int>(i1));
      }
    }
    ++it1;
    ++it2;
  }
  if (orient) {
    int ind1, ind2, ind3;
    features::ComputeThreeMaxima(hist, &ind1, &ind2, &ind3);
    for (int b = 0; b < features::kHistoLength; ++b) {
      if (b == ind1 || b == ind2 || b == ind3) continue;
      for (int i1 : hist[b]) out[i1] = -1;
    }
  }
  return out;
}

int SearchByProjectionPose(const KeyFrame& kf, const SE3& T_cw, const std::vector<int64_t>& points, const Map& map,
                           float th, std::vector<int64_t>* matched) {
  const Frame& f = kf.frame;
  std::set<int64_t> already;
  for (int64_t id : *matched)
    if (id >= 0) already.insert(id);
  int added = 0;
  for (int64_t id : points) {
    const MapPoint* p = map.good_mp(id);
    if (p == nullptr || already.count(id)) continue;
    Window w;
    if (!Project(kf, T_cw, *p, th, &w)) continue;
    float best = f.match_profile.worst;
    int best_idx = -1;
    for (int i : f.FeaturesInArea(static_cast<float>(w.u), static_cast<float>(w.v), static_cast<float>(w.radius))) {
      if ((*matched)[i] >= 0 || f.IsExcluded(i)) continue;
      const int level = f.keys_un[i].octave;
      if (level < w.level - 1 || level > w.level) continue;
      const float d = features::RowDistance(p->descriptor, 0, f.descriptors, i);
      if (d < best) {
        best = d;
        best_idx = i;
      }
    }
    if (best_idx >= 0 && best <= f.match_profile.th_low) {
      (*matched)[best_idx] = id;
      already.insert(id);
      ++added;
    }
  }
  return added;
}

FuseResult FusePose(const KeyFrame& kf, const SE3& T_cw, const std::vector<int64_t>& points, const Map& map, float th) {
  FuseResult out;
  const Frame& f = kf.frame;
  std::vector<int> taken(kf.N(), 0);  // a feature receives at most one fused point per call
  for (int64_t id : points) {
    const MapPoint* p = map.good_mp(id);
    if (p == nullptr || p->observations.count(kf.id)) continue;
    Window w;
    if (!Project(kf, T_cw, *p, th, &w)) continue;
    float best = f.match_profile.worst;
    int best_idx = -1;
    for (int i : f.FeaturesInArea(static_cast<float>(w.u), static_cast<float>(w.v), static_cast<float>(w.radius))) {
      if (taken[i] || f.IsExcluded(i)) continue;
      const int level = f.keys_un[i].octave;
      if (level < w.level - 1 || level > w.level) continue;
      const float d = features::RowDistance(p->descriptor, 0, f.descriptors, i);
      if (d < best) {
        best = d;
        best_idx = i;
      }
    }
    if (best_idx < 0 || best > f.match_profile.th_low) continue;
    taken[best_idx] = 1;
    const int64_t own = kf.map_point_ids[best_idx];
    if (own >= 0 && map.good_mp(own) != nullptr) out.replace.emplace_back(own, id);
    else out.add.emplace_back(best_idx, id);
  }
  return out;
}

}  // namespace dynref::loop
