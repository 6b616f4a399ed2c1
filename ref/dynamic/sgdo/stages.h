// The sgdo components (see register.h for the hook of each). Internal to dynamic/sgdo;
// constructed by the MethodRegistry factories from a config's ParamMap and the run's
// SharedState. Every parameter is required in the config (with its source), unknown keys are
// errors.
#pragma once
#include <memory>
#include <string>

#include "dynamic/sgdo/coarse.h"
#include "dynamic/sgdo/depth_consistency.h"
#include "dynamic/sgdo/stage_common.h"
#include "geometry/fundamental.h"
#include "geometry/lk_pairs.h"
#include "method/detection_tally.h"

namespace dynref::sgdo {

class MaskStage : public Stage {
 public:
  MaskStage(const ParamMap& params, std::shared_ptr<Blackboard> board);
  std::string name() const override { return "sgdo.mask"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override;
  void Finish(RunEnd& end) override { tally_.Report(end); }

 private:
  std::shared_ptr<Blackboard> board_;
  DynamicMaskOptions options_;
  bool reject_in_mask_ = false;
  DetectionTally tally_;  // dynamic-class instances seen / dropped by min_confidence (issue 39)
};

class CoarseStage : public Stage {
 public:
  CoarseStage(const ParamMap& params, std::shared_ptr<Blackboard> board);
  std::string name() const override { return "sgdo.coarse"; }
  Hook hook() const override { return Hook::kBeforeInitialPose; }
  void Run(StageContext& ctx) override;

 private:
  std::shared_ptr<Blackboard> board_;
  geometry::LkOptions lk_;
  geometry::RansacOptions ransac_;
  CoarseOptions coarse_;
  Rng rng_;
};

class DepthStage : public Stage {
 public:
  explicit DepthStage(const ParamMap& params);
  std::string name() const override { return "sgdo.depth"; }
  Hook hook() const override { return Hook::kAfterInitialPose; }
  void Run(StageContext& ctx) override;

 private:
  DepthConsistencyOptions options_;
  bool reject_ = true;   // (S+G+D), (S+G+D+O)
  bool weight_ = true;   // (O), (S+G+O), (S+G+D+O)
};


}  // namespace dynref::sgdo
