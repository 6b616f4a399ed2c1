// seed 003 compensation and depth fusion measured against the synthetic ground truth: the
// blur.mask builder (dynamic/blur/fused_mask.h, the code the stage runs) is replayed on a
// sequence's detections and depth, and every frame's mask parts are compared with the true person
// pixels (SEQ/gt/, scene ids 1..19 are people). "missed" = true person pixels the segmenter's
// masks do not cover; compensation and depth fusion recover part of them and add false pixels.
#pragma once
#include <cstdint>
#include <string>

#include "dynamic/blur/fused_mask.h"

namespace dynref::reproduce {

struct MaskTruth {
  int frames = 0;
  int frames_with_missed = 0;        // frames where >= 5 % of the true person pixels are missed
  int frames_triggered = 0;          // compensation trigger r < r_threshold
  int64_t person_px = 0;             // true person pixels, all frames
  int64_t missed_px = 0;             // of them not in the segmenter's masks
  int64_t comp_px = 0, comp_recovered_px = 0, comp_false_px = 0;     // pasted pixels
  int64_t depth_px = 0, depth_recovered_px = 0, depth_false_px = 0;  // depth-fused pixels added
  int64_t final_px = 0, final_covered_px = 0;  // M_sd (after dilation) and the person pixels it covers
  MaskTruth& operator+=(const MaskTruth& o);      // sums (over seeds)
};

// Replays `options` on SEQ with SEQ/detections/<mode>; InputError if a file is missing or bad.
MaskTruth MeasureMaskTruth(const std::string& seq_dir, const std::string& detections_mode,
                           const blur::FusedMaskOptions& options);

}  // namespace dynref::reproduce
