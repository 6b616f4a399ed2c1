// The sgdo pipeline stages (see register.h for the hook of each). Internal to dynamic/sgdo;
// constructed by the StageRegistry factories from a config's ParamMap. Every parameter is
// required in the config (with its source), unknown keys are errors.
#pragma once
#include <memory>
#include <string>

#include "dense/dense_map.h"
#include "dense/ply_writer.h"
#include "dynamic/sgdo/coarse.h"
#include "dynamic/sgdo/depth_consistency.h"
#include "dynamic/sgdo/fundamental.h"
#include "dynamic/sgdo/lk_pairs.h"
#include "dynamic/sgdo/stage_common.h"

namespace dynref::sgdo {

class MaskStage : public Stage {
 public:
  MaskStage(const ParamMap& params, std::shared_ptr<Blackboard> board);
  std::string name() const override { return "sgdo.mask"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override;

 private:
  std::shared_ptr<Blackboard> board_;
  DynamicMaskOptions options_;
  bool reject_in_mask_ = false;
};

class CoarseStage : public Stage {
 public:
  CoarseStage(const ParamMap& params, std::shared_ptr<Blackboard> board);
  std::string name() const override { return "sgdo.coarse"; }
  Hook hook() const override { return Hook::kBeforeInitialPose; }
  void Run(StageContext& ctx) override;

 private:
  std::shared_ptr<Blackboard> board_;
  LkOptions lk_;
  RansacOptions ransac_;
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

class DenseMapStage : public Stage {
 public:
  DenseMapStage(const ParamMap& params, std::shared_ptr<Blackboard> board);
  ~DenseMapStage() override;  // writes the PLY if frames were processed and not yet written
  std::string name() const override { return "sgdo.densemap"; }
  Hook hook() const override { return Hook::kOnKeyFrameCreated; }
  void Run(StageContext& ctx) override;
  // Final filter + atomic PLY write. Idempotent.
  void WriteMap();

 private:
  std::shared_ptr<Blackboard> board_;
  dense::DenseMapOptions options_;
  std::string output_path_;
  dense::PlyFormat format_ = dense::PlyFormat::kBinaryLittleEndian;
  std::unique_ptr<dense::DenseMap> map_;
  bool written_ = false;
  bool resolved_ = false;
  bool tr_no_output_ = false;
};

}  // namespace dynref::sgdo
