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
  // Under --blur (seed 003's failure): an instance whose image-space blur streak is L px
  // (centroid speed in px/frame x exposure in frames, capped at blur_max_px) enters a missed burst with the extra
  // probability min(blur_drop_max, blur_drop_per_px * L); if still detected, with probability
  // min(blur_shrink_max, blur_shrink_per_px * L) its mask loses the blurred fringe (eroded by
  // round(blur_shrink_depth * L) px). Without --blur none of this applies (L = 0).
  double blur_drop_per_px = 0;
  double blur_drop_max = 0;
  double blur_shrink_per_px = 0;
  double blur_shrink_max = 0;
  double blur_shrink_depth = 0;
  double blur_max_px = 30;       // L is capped: a centroid jump by partial visibility is not blur
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

// What the degradation did to one GT instance in one frame (gt/dropped-<mode>.txt), so that a
// method compensating missed segmentations (seed 003) is measured against truth.
struct DegradeEvent {
  int gt_id = 0;
  std::string what;        // missed | small-missed | shrunk | overpainted
  double blur_px = 0;      // blur streak length L of the instance in this frame
  int shrink_px = 0;       // erosion radius when shrunk
};

class Degrader {
 public:
  // blur_exposure_frames: exposure time in frame intervals (exposure_s * fps) when the sequence
  // is rendered with --blur, 0 without blur.
  Degrader(const DegradeProfile& profile, const std::map<int, InstanceLabel>& labels, uint64_t seed,
           double blur_exposure_frames);
  FrameDetections Apply(int frame_index, const GtFrame& gt);
  // Events of the last Apply, ascending GT id.
  const std::vector<DegradeEvent>& events() const { return events_; }

 private:
  DegradeProfile p_;
  std::map<int, InstanceLabel> labels_;
  uint64_t seed_;
  double blur_exposure_frames_;
  std::map<int, bool> missed_;            // per GT instance: in a missed burst
  std::map<int, cv::Point2d> centroid_;   // per GT instance: centroid in the previous frame
  int previous_frame_ = -2;
  std::vector<DegradeEvent> events_;
};

// One line of gt/dropped-<mode>.txt: "stamp id:what:blur_px[:shrink_px] ..." (see datasets/README.md).
std::string DegradeEventsLine(const std::string& stamp, const std::vector<DegradeEvent>& events);

// Ground-truth record of a frame: every labelled instance with pixels, confidence 1, tight box.
FrameDetections GtDetections(const GtFrame& gt, const std::map<int, InstanceLabel>& labels);

}  // namespace dynref::synth
