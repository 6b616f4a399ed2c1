// MGD-SLAM (seed 000) stages: points and, when the config turns the backbone's lines on, line
// samples (line_samples.h). See register.h for hooks, README.md for the equations and readings.
#pragma once
#include <memory>
#include <string>

#include "dynamic/mgd/options.h"
#include "dynamic/mgd/state.h"
#include "method/detection_tally.h"
#include "method/params.h"
#include "method/stage.h"

namespace dynref::mgd {

// Reads every option from mgd.probability's params (all keys required, with their sources).
MgdOptions ReadOptions(const ParamMap& p);
// The options of the run; std::logic_error naming `stage` when mgd.probability is not configured.
const MgdOptions& RequireOptions(const MgdState& state, const std::string& stage);

// Flag_d (Sec. 3.3): (u, v) inside a box with confidence > min_confidence of a dynamic class.
// The confidence is compared with min_confidence mapped to det->source (threshold_scale, issue 39).
bool InKeptBox(const FrameDetections* det, const MgdOptions& o, float u, float v);

class BoxStage : public Stage {
 public:
  explicit BoxStage(std::shared_ptr<MgdState> state) : state_(std::move(state)) {}
  std::string name() const override { return "mgd.boxes"; }
  Hook hook() const override { return Hook::kBeforeInitialPose; }
  void Run(StageContext& ctx) override;
  void Finish(RunEnd& end) override;  // dynamic-class boxes seen / dropped by min_confidence

 private:
  std::shared_ptr<MgdState> state_;
  std::unique_ptr<DetectionTally> tally_;  // from mgd.probability's options at the first frame
};

class ProbabilityStage : public Stage {
 public:
  ProbabilityStage(const MgdOptions& o, std::shared_ptr<MgdState> state);
  std::string name() const override { return "mgd.probability"; }
  // After the local-map search (paper Sec. 3.4, issue 38), or after the initial pose.
  Hook hook() const override { return o_.after_local_map_search ? Hook::kBeforeFinalPose : Hook::kAfterInitialPose; }
  void Run(StageContext& ctx) override;

 private:
  MgdOptions o_;
  std::shared_ptr<MgdState> state_;
};

class ReprojectionStage : public Stage {
 public:
  explicit ReprojectionStage(std::shared_ptr<MgdState> state) : state_(std::move(state)) {}
  std::string name() const override { return "mgd.reprojection"; }
  Hook hook() const override { return Hook::kOnMapUpdate; }
  void Run(StageContext& ctx) override;
  void OnLandmarkEvent(const LandmarkEvent& e) override;

 private:
  std::shared_ptr<MgdState> state_;
};

}  // namespace dynref::mgd
