// seed 001, Sec. 3.2: dynamic mask M = union of the instance masks of prior-dynamic classes,
// "appropriately expanded" by a morphological dilation (kernel not stated: spec 001 E3).
#pragma once
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <vector>

#include "io/mask_format.h"

namespace dynref::geometry {

struct DynamicMaskOptions {
  std::vector<int> dynamic_class_ids = {0};  // COCO ids; default {person} (spec 001 (c))
  double min_confidence = 0.25;              // not stated; ultralytics default
  int dilation_kernel_px = 15;               // square kernel side, odd, 1 = no dilation
  // Throws std::invalid_argument naming the bad field.
  void Check() const;
};

struct DynamicMask {
  cv::Mat mask;        // CV_8U, 255 = in M (dilated union), 0 = outside
  // CV_16U, per pixel the id of the (dilated) dynamic instance covering it, 0 = none.
  // Overlaps: the lowest instance id wins (instances are dilated in ascending id order and a
  // pixel keeps the first label it receives).
  cv::Mat instance_labels;
  std::vector<int> instance_ids;  // dynamic instances used, ascending id
  bool InMask(double u, double v) const;
  int InstanceAt(double u, double v) const;  // 0 outside M or outside the image
};

// Builds M for one frame of size (width, height). Instances without a pixel mask (boxes only)
// contribute their box, clipped to the image (detector-only sources).
DynamicMask BuildDynamicMask(const FrameDetections& detections, int width, int height,
                             const DynamicMaskOptions& options);

// The same mask built from a given set of instance ids (e.g. prior-dynamic plus the static
// objects a method judged dynamic, seed 002). std::invalid_argument for an even or < 1 kernel.
DynamicMask BuildInstanceMask(const FrameDetections& detections, int width, int height,
                              const std::set<int>& instance_ids, int dilation_kernel_px);

// Instance-level mask of the non-dynamic (static) recognised classes, CV_16S class id per
// pixel (-1 = none), without dilation; used for class colouring of the dense map (Sec. 3.6).
cv::Mat StaticClassLabels(const FrameDetections& detections, int width, int height,
                          const DynamicMaskOptions& options);

}  // namespace dynref::geometry
