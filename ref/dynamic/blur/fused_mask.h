// M_sd of one frame (spec 003 steps 1-3): the segmenter's person masks, missed-segmentation
// compensation, depth fusion of every person box after compensation, dilation, with the origin of
// every mask pixel. One builder per run (it keeps the compensation tracks and the sampling
// stream); the blur.mask stage and the truth measurement of `dynref reproduce blur-table3` both
// use it, so what is measured is what runs.
#pragma once
#include <memory>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/rng.h"
#include "dynamic/blur/compensation.h"
#include "dynamic/blur/depth_fusion.h"
#include "io/mask_format.h"

namespace dynref::blur {

// Origin of a pixel of M_sd (overlay colours, trace counts); the first origin that set it wins.
enum MaskOrigin : uint8_t { kNone = 0, kSegmenter = 1, kCompensation = 2, kDepthFusion = 3, kDilation = 4 };

struct FusedMaskOptions {
  std::set<int> person_class_ids = {0};  // humans only (paper Sec. 3.1)
  double min_confidence = 0.5;
  bool compensation = true;
  CompensationOptions comp;
  bool depth_fusion = true;
  DepthFusionOptions depth;
  int dilation_size = 10;                // kernel (2*size+1)^2 rectangle; 0 = no dilation
  uint64_t sampling_seed = 1;
  void Check() const;                    // std::invalid_argument naming the field
};

struct BoxFusion {
  cv::Rect box;
  HumanValueRange range;
  int added_px = 0;                      // pixels M_d^i added to the mask built so far
};

struct FusedMask {
  std::vector<PersonMask> persons;       // the segmenter's persons (ascending detection id)
  CompensationResult comp;
  std::vector<BoxFusion> fusion;
  cv::Mat mask;                          // CV_8U 0/255, M_sd after dilation
  cv::Mat origin;                        // CV_8U MaskOrigin per pixel
};

class FusedMaskBuilder {
 public:
  FusedMaskBuilder(const FusedMaskOptions& options, cv::Size image_size);  // std::invalid_argument
  // InputError (naming `source`) for a detection mask whose size differs from the image.
  // `min_confidence` < 0: the options' value; else the threshold the stage applies to this
  // source's raw confidences (issue 39, detect/score_calibration.h).
  FusedMask Build(const FrameDetections& detections, const cv::Mat& depth_m, double stamp, const std::string& source,
                  double min_confidence = -1);

 private:
  FusedMaskOptions o_;
  cv::Size size_;
  MissedSegmentationCompensator compensator_;
  Rng rng_;
};

}  // namespace dynref::blur
