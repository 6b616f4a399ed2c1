// Shared state and parameter helpers of the sgdo stages (internal to dynamic/sgdo).
#pragma once
#include <memory>
#include <set>
#include <string>

#include "dynamic/sgdo/dynamic_mask.h"
#include "pipeline/stage.h"

namespace dynref::sgdo {

// Per-run blackboard shared by the sgdo stages of one registry: the dynamic mask M of the
// frame being processed (written by sgdo.mask, read by sgdo.coarse and sgdo.densemap). Keyed by
// frame index + stamp so a stale mask of another frame is never used.
struct Blackboard {
  int frame_index = -1;
  std::string stamp_text;
  DynamicMask mask;
  DynamicMaskOptions mask_options;
  cv::Mat static_labels;  // CV_16S recognised static classes (for dense colouring)
  bool Has(const Frame& f) const { return frame_index == f.index && stamp_text == f.stamp_text; }
};

// InputError naming the config file/line for a key not in `known`.
void RequireKnownKeys(const ParamMap& params, const std::set<std::string>& known);

// The frame's detections; InputError if the run has none for this frame (mask-based variants
// need `--detections`).
const FrameDetections& RequireDetections(const Frame& frame, const std::string& stage);

}  // namespace dynref::sgdo
