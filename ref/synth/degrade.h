// Deterministic stand-ins for the detectors/segmenters the papers used: `ideal` copies the
// ground truth; `yolo-like` and `sparseinst-like` degrade it with documented error rates
// (datasets/README.md, "Detection degradation"): boundary jitter, missing limbs, missed
// detections in bursts (more under blur), low-confidence false positives on static objects,
// class confusion.
#pragma once
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/rng.h"
#include "io/mask_format.h"
#include "synth/scene.h"

namespace dynref::synth {

struct DegradeProfile {
  std::string name;
  double miss_enter = 0;         // P(detected -> missed) per frame
  double miss_stay = 0;          // P(missed -> missed): mean burst length 1 / (1 - miss_stay)
  double blur_miss_factor = 1;   // miss_enter multiplier with --blur
  double small_miss = 0;         // extra per-frame miss probability below small_area_px
  int small_area_px = 2000;
  int min_area_px = 1;           // instances smaller than this are never detected
  int boundary_jitter_px = 0;    // mask boundary moves by up to this many pixels (wavy)
  double limb_drop = 0;          // P(a person mask loses a forearm/shin) per frame
  double false_positive = 0;     // P(one low-confidence false positive on a static object) per frame
  double confusion = 0;          // P(class replaced by a confusable class), non-person
  double person_confusion = 0;   // same for persons
  int box_jitter_px = 0;         // box edges move by up to this many pixels
  double conf_lo = 1, conf_hi = 1;
};

DegradeProfile ProfileFor(const std::string& mode);  // ideal | yolo-like | sparseinst-like

struct GtFrame {
  std::string stamp_text;
  cv::Mat instance_ids;          // CV_16U scene instance ids
  cv::Mat body_part;             // CV_8S BodyPart per pixel (-1 = not a person part)
  cv::Mat depth_m;               // CV_32F true depth
};

class Degrader {
 public:
  Degrader(const DegradeProfile& profile, const std::map<int, InstanceLabel>& labels, uint64_t seed, bool blur);
  FrameDetections Apply(int frame_index, const GtFrame& gt);

 private:
  DegradeProfile p_;
  std::map<int, InstanceLabel> labels_;
  uint64_t seed_;
  bool blur_;
  std::map<int, bool> missed_;   // per GT instance: in a missed burst
};

// Ground-truth record of a frame: every labelled instance with pixels, confidence 1, tight box.
FrameDetections GtDetections(const GtFrame& gt, const std::map<int, InstanceLabel>& labels);

}  // namespace dynref::synth
