// Per-run state shared by the MGD-SLAM stages (SharedState key kStateKey).
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "dynamic/mgd/options.h"

namespace dynref::mgd {

constexpr const char* kStateKey = "mgd.state";

// The long-term cue of one map point, computed at the keyframe that observed it last (spec E7).
struct ProCue {
  double mean_forward_px = 0, mean_backward_px = 0, p = 0.5;
  int covisible = 0;  // K_n: covisible keyframes that observe the point
  int64_t kf = -1;
  int64_t mp = -1;  // the map point it was computed for (a replaced point's cue moves to its replacement)
};

struct MgdState {
  // The method's options: read once from mgd.probability's params (the other stages take none).
  MgdOptions options;
  bool configured = false;
  // Current frame (set by mgd.boxes).
  int frame = -1;
  std::string stamp;
  std::vector<uint8_t> in_box;  // Flag_d per feature
  std::vector<std::array<uint8_t, 3>> line_in_box;  // Flag_d per line sample s, m, e
  // Previous processed frame: P per feature (-1 = none), by feature index.
  int prev_frame = -1;
  std::vector<double> prev_p;
  std::vector<std::array<double, 3>> prev_line_p;  // per previous-frame line and sample (-1 = none)
  // P_pro per map point (mgd.reprojection), kept current through landmark events.
  std::map<int64_t, ProCue> pro;
};

}  // namespace dynref::mgd
