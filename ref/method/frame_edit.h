// The narrow handle through which a stage changes a frame (issue 12): it reads everything of
// the frame through view(), and may only
//   - exclude a feature (never matched, never optimised, never creates a map point),
//   - set a feature's weight (multiplies its residual information in pose optimisation and, on
//     a keyframe, in local BA),
//   - set a landmark's dynamic probability (map/landmark.h; the backbone never reads it),
//   - at kBeforeExtraction only: replace the grey image feature extraction will see.
// Anything else a stage wants to keep (masks, per-feature probabilities) is its own state.
#pragma once
#include <opencv2/core.hpp>
#include <string>

#include "map/frame.h"
#include "map/map.h"
#include "method/hooks.h"

namespace dynref {

class FrameEdit {
 public:
  FrameEdit(Frame& frame, Map& map, Hook hook) : frame_(frame), map_(map), hook_(hook) {}
  const Frame& view() const { return frame_; }
  Hook hook() const { return hook_; }
  void set_hook(Hook hook) { hook_ = hook; }

  // Frame::Exclude / Frame::SetWeight (frame.h); std::logic_error before extraction.
  void Exclude(int i, const std::string& stage, const std::string& reason);
  void SetWeight(int i, double w);
  // std::logic_error for an unknown point id or p outside [0, 1].
  void SetPointDynamicProbability(int64_t mp_id, double p, const std::string& stage);
  // Line i's weight (FrameStructure::line_weight) in [0, 1]; 0 takes the line out of pose
  // optimisation, local BA and the map (like an excluded point). std::logic_error for a bad
  // index or w outside [0, 1], or before extraction.
  void SetLineWeight(int i, double w);
  // Map line's dynamic probability (std::logic_error for an unknown line or p outside [0, 1]).
  void SetLineDynamicProbability(int64_t ml_id, double p, const std::string& stage);
  // The grey image extraction will run on (same size and type CV_8U required when replaced);
  // std::logic_error at any other hook than kBeforeExtraction.
  cv::Mat& grey_for_extraction();

 private:
  void RequireFeatures(const char* what) const;
  Frame& frame_;
  Map& map_;
  Hook hook_;
};

}  // namespace dynref
