// Shared state and parameter helpers of the sgdo stages (internal to dynamic/sgdo).
#pragma once
#include <memory>
#include <set>
#include <string>

#include "geometry/dynamic_mask.h"
#include "core/error.h"
#include "method/params.h"
#include "method/stage.h"

namespace dynref::sgdo {

using geometry::BuildDynamicMask;
using geometry::DynamicMask;
using geometry::DynamicMaskOptions;
using geometry::StaticClassLabels;

// Per-run blackboard shared by the sgdo components of one Session (SharedState key kBoardKey):
// the dynamic mask M of the frame being processed (written by sgdo.mask, read by sgdo.coarse and
// the sgdo.densemap map module). Keyed by frame index + stamp so a stale mask of another frame is
// never used.
struct Blackboard {
  int frame_index = -1;
  std::string stamp_text;
  DynamicMask mask;
  DynamicMaskOptions mask_options;
  cv::Mat static_labels;  // CV_16S recognised static classes (for dense colouring)
  bool Has(const Frame& f) const { return frame_index == f.index && stamp_text == f.stamp_text; }
};

constexpr const char* kBoardKey = "sgdo.board";

// The frame's detections; InputError if the run has none for this frame (mask-based variants
// need `--detections`).
const FrameDetections& RequireDetections(const Frame& frame, const std::string& stage);

}  // namespace dynref::sgdo
