// Temporal association of detections across frames (issue 39): a person the detector misses for
// one or two frames (motion blur: TUM fr3 walking_halfsphere frames .914148 and .946443) keeps an
// identity and a box. The same mechanism as seed 003's missed-segmentation compensation
// (ref/dynamic/blur/compensation.h, spec 003 E3): association by box IoU >= iou_link with the
// track's last detected box, and a lost track's box moved along the least-squares line through
// its last `history` top-left corners against time (Sec. 3.1). Differences: it works on boxes
// of any listed class in `dynref detect` (so every method sees the carried boxes), and it carries
// a track only for max_gap frames without a trigger on the mask area.
#pragma once
#include <map>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <vector>

#include "io/mask_format.h"

namespace dynref::detect {

struct TemporalOptions {
  int max_gap = 2;          // frames a track is carried without a detection (0 = off)
  double iou_link = 0.3;    // blur.mask iou_found (spec 003 E3)
  int history = 3;          // corners in the line fit (paper 003 Sec. 3.1: n = 3)
  std::set<int> class_ids = {0};  // COCO ids tracked (person)
  void Check() const;       // std::invalid_argument naming the field
};

// One instance of an output frame and its track.
struct TrackLink {
  int instance_id = 0;
  int track = 0;
  bool carried = false;     // added by the linker (box only, the track's last confidence)
};

class TemporalLinker {
 public:
  TemporalLinker(const TemporalOptions& options, cv::Size image_size);
  // Frames in order. Returns `in` with one box-only instance appended (ids after the largest
  // in `in`) per carried track; `links` gets the track of every tracked-class instance.
  FrameDetections Process(const FrameDetections& in, double stamp_s, std::vector<TrackLink>* links);
  int carried_total() const { return carried_total_; }

 private:
  struct Track {
    int id = 0, class_id = 0, missed = 0;
    std::string class_name;
    double confidence = 0;
    cv::Rect2d box;                         // last detected box
    std::vector<cv::Point3d> corners;       // (x_min, y_min, t) of the last detections
  };
  TemporalOptions o_;
  cv::Size size_;
  std::map<int, Track> tracks_;  // by id
  int next_track_ = 1, carried_total_ = 0;
};

// Least-squares line through (x, y) against t of the samples, evaluated at t_c, time centred on
// t_c (seed 003 Sec. 3.1; the same fit as blur::PredictCorner). 1 sample: itself.
cv::Point2d PredictCornerLsq(const std::vector<cv::Point3d>& samples, double t_c);

}  // namespace dynref::detect
