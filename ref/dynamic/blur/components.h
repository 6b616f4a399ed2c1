// Motion-blur SLAM (seed 003) components; see register.cpp and README.md.
//   blur.mask         (kAfterExtraction) person masks -> missed-segmentation compensation ->
//                     depth fusion -> dilation = M_sd, with the origin of every mask pixel
//   blur.probability  (kAfterExtraction, after blur.mask) Eq. (20) + k-d tree probabilities,
//                     keypoints with P > theta excluded before any matching
#pragma once
#include <map>
#include <memory>
#include <set>
#include <string>

#include "dynamic/blur/fused_mask.h"
#include "dynamic/blur/keypoint_probability.h"
#include "io/mask_layers.h"
#include "method/detection_tally.h"
#include "method/params.h"
#include "method/stage.h"

namespace dynref::blur {

constexpr const char* kBoardKey = "blur.board";

// The current frame's M_sd, written by blur.mask and read by blur.probability.
struct Board {
  int frame = -1;
  std::string stamp;
  cv::Mat mask;     // CV_8U 0/255, M_sd after dilation
  cv::Mat origin;   // CV_8U MaskOrigin per pixel
  bool Has(const Frame& f) const { return frame == f.index && stamp == f.stamp_text; }
};

// blur.mask's parameters (configs/blur*.yaml); InputError naming file:line for a bad value.
FusedMaskOptions MaskOptionsFromParams(const ParamMap& p);

class MaskStage : public Stage {
 public:
  MaskStage(const ParamMap& p, std::shared_ptr<Board> board);
  std::string name() const override { return "blur.mask"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override;
  // RUN/masks/ (io/mask_layers.h): the origin of every mask pixel per frame, when write_mask_layers.
  void Finish(RunEnd& end) override;

 private:
  FusedMaskOptions o_;
  std::shared_ptr<Board> board_;
  std::unique_ptr<FusedMaskBuilder> builder_;  // created at the first frame (image size)
  std::unique_ptr<MaskLayersWriter> layers_;   // null unless write_mask_layers
  std::map<int, std::string> track_entity_;    // trace full: entity of every live track's last state
  DetectionTally tally_;                        // persons seen / dropped by min_confidence (issue 39)
  void TraceMask(trace::TraceWriter& tr, const Frame& f, const FusedMask& m);
};

class ProbabilityStage : public Stage {
 public:
  ProbabilityStage(const ParamMap& p, std::shared_ptr<Board> board);
  std::string name() const override { return "blur.probability"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override;

 private:
  KeypointProbabilityOptions o_;
  std::shared_ptr<Board> board_;
};

}  // namespace dynref::blur
