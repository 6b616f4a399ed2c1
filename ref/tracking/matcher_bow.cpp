// ORBmatcher::SearchByBoW for a keyframe and a frame; see matcher_bow.h.
#include "tracking/matcher_bow.h"

#include <vector>

#include "features/descriptor.h"

namespace dynref::tracking {
namespace {

// Keeps matches whose rotation bin is one of the three fullest (ORBmatcher's rotHist check).
int DropInconsistentRotations(const std::vector<std::vector<int>>& hist, Frame& cur) {
  int ind1, ind2, ind3;
  features::ComputeThreeMaxima(hist, &ind1, &ind2, &ind3);
  int removed = 0;
  for (int b = 0; b < features::kHistoLength; ++b) {
    if (b == ind1 || b == ind2 || b == ind3) continue;
    for (int idx : hist[b])
      if (cur.map_point_ids[idx] >= 0) {
        cur.map_point_ids[idx] = -1;
        ++removed;
      }
  }
  return removed;
}

}  // namespace

int SearchByBoW(const KeyFrame& kf, const PlaceBow& kf_bow, Frame& cur, const PlaceBow& cur_bow, const Map& map,
                float nn_ratio, bool check_orientation) {
  std::vector<std::vector<int>> hist(features::kHistoLength);
  const bool orient = check_orientation && cur.match_profile.oriented;
  const float worst = cur.match_profile.worst;
  const Frame& kff = kf.frame;
  int n = 0;
  auto kit = kf_bow.features.begin();
  auto fit = cur_bow.features.begin();
  while (kit != kf_bow.features.end() && fit != cur_bow.features.end()) {
    if (kit->first < fit->first) {
      kit = kf_bow.features.lower_bound(fit->first);
      continue;
    }
    if (fit->first < kit->first) {
      fit = cur_bow.features.lower_bound(kit->first);
      continue;
    }
    for (uint32_t i : kit->second) {
      const int64_t id = kf.map_point_ids[i];
      if (id < 0 || map.good_mp(id) == nullptr) continue;
      float best1 = worst, best2 = worst;
      int best_idx = -1;
      for (uint32_t j : fit->second) {
        if (cur.map_point_ids[j] >= 0 || cur.IsExcluded(static_cast<int>(j))) continue;
        const float d = features::RowDistance(kff.descriptors, static_cast<int>(i), cur.descriptors, static_cast<int>(j));
        if (d < best1) {
          best2 = best1;
          best1 = d;
          best_idx = static_cast<int>(j);
        } else if (d < best2) {
          best2 = d;
        }
      }
      if (best_idx >= 0 && best1 <= cur.match_profile.th_low && best1 < nn_ratio * best2) {
        cur.map_point_ids[best_idx] = id;
        ++n;
        if (orient) hist[features::RotationBin(kff.keys_un[i].angle, cur.keys_un[best_idx].angle)].push_back(best_idx);
      }
    }
    ++kit;
    ++fit;
  }
  if (orient) n -= DropInconsistentRotations(hist, cur);
  return n;
}

}  // namespace dynref::tracking
