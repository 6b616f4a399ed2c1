// One keyframe observation of a map point as the bundle adjusters take it (local BA, and loop
// closing's global BA): undistorted pixel, right-image coordinate, level weight, the method's
// static weight and the feature index for the trace's link record.
#pragma once
#include <cstdint>

#include "map/map.h"
#include "optim/optim.h"

namespace dynref {

inline optim::BAObservation KeyframeObservation(const KeyFrame& k, int64_t kf_id, int64_t point_id, int idx) {
  optim::BAObservation o;
  o.kf_id = kf_id;
  o.point_id = point_id;
  o.uv = {k.frame.keys_un[idx].pt.x, k.frame.keys_un[idx].pt.y};
  o.u_right = k.frame.u_right[idx];
  o.inv_sigma2 = k.frame.pyramid.inv_sigma2[k.frame.keys_un[idx].octave];
  o.weight = k.frame.Weight(idx);
  o.trace_feature = idx;  // link record (optim.h)
  return o;
}

}  // namespace dynref
