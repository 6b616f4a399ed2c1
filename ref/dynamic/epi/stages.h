// Enhanced-epipolar SLAM (seed 004) stages; see register.cpp and README.md.
//   epi.enhance  (kBeforeExtraction) Module A: the grey image ORB extraction sees is enhanced;
//                (alpha, p) tuned once by butterfly optimisation on the first frame, or fixed.
//   epi.vote     (kAfterExtraction)  Module C: static region outside prior-dynamic masks, relative
//                pose from its LK pairs (RGB-D rigid RANSAC), F = K^-T [t]x R K^-1, epipolar
//                distance of every in-mask keypoint, 60 % vote per mask, dynamic masks' keypoints
//                excluded before any matching.
//   epi.nerf     (map module)        Sec. 3.3.2: NeRF-ready export at the end of the run
//                (nerf_export.h): keyframe images, Module C's dynamic masks, transforms.json,
//                pseudo-point cloud of triangulated static matches, L_geo.
// Module B is the backbone's feature plug-in (ref/features/keypoint_extractor.h: SIFT or a
// SuperPoint-style ONNX model, MNN2 matching; configs/epi_B.yaml, epi_BC.yaml, epi_ALL.yaml).
#pragma once
#include <map>
#include <set>
#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "dynamic/epi/butterfly.h"
#include "dynamic/epi/enhance.h"
#include "dynamic/epi/mask_vote.h"
#include "dynamic/epi/nerf_export.h"
#include "features/mnn2.h"
#include "geometry/dynamic_mask.h"
#include "geometry/lk_pairs.h"
#include "geometry/rigid_ransac.h"
#include "method/detection_tally.h"
#include "method/map_module.h"
#include "method/params.h"
#include "method/stage.h"

namespace dynref::epi {

struct EnhanceStageOptions {
  EnhanceParams params;
  bool optimise = true;          // BOA on the first frame (spec 004 E2: once per sequence)
  BoaOptions boa;
  double alpha_max = 2.0, p_min = 0.25, p_max = 3.0;  // BOA search box (not stated)
  uint64_t seed = 1;
};
EnhanceStageOptions EnhanceOptionsFromParams(const ParamMap& p);

// Tunes (alpha, p) of `params` on one grey image by BOA; returns the result (params updated).
// threads: the run's --threads (enhance.h), the same result for any count.
BoaResult OptimiseEnhancement(const cv::Mat& grey8, const EnhanceStageOptions& o, EnhanceParams* params, Rng& rng,
                              int threads = 1);

// Module A over a sequence (spec 004 E2): with `optimise`, (alpha, p) are tuned by BOA
// (Rng(seed, "epi.boa")) on the first image enhanced, then kept for every later image. The
// epi.enhance stage, `dynref enhance` and `reproduce epi-table1` all enhance through it.
class SequenceEnhancer {
 public:
  explicit SequenceEnhancer(const EnhanceStageOptions& o) : o_(o), rng_(o.seed, "epi.boa") {}
  // `tuned` (optional) receives the BOA result on the call that tuned (evaluations 0 otherwise).
  EnhanceResult Enhance(const cv::Mat& grey8, BoaResult* tuned = nullptr, int threads = 1);
  const EnhanceParams& params() const { return o_.params; }

 private:
  EnhanceStageOptions o_;
  Rng rng_;
  bool tuned_ = false;
  EnhanceBuffers buffers_;  // full-image buffers kept from frame to frame
};

class EnhanceStage : public Stage {
 public:
  explicit EnhanceStage(const ParamMap& p);
  std::string name() const override { return "epi.enhance"; }
  Hook hook() const override { return Hook::kBeforeExtraction; }
  void Run(StageContext& ctx) override;

 private:
  SequenceEnhancer enhancer_;
};

// What epi.vote leaves for epi.nerf: the current frame's instance labels and the ids voted
// dynamic (epi.nerf draws the pixel mask at keyframes only).
struct Blackboard {
  int frame_index = -1;
  std::string stamp_text;
  cv::Mat instance_labels;       // CV_16U (geometry::DynamicMask), empty: no mask
  std::set<int> dynamic_ids;     // instances voted dynamic
  bool Has(const Frame& f) const { return frame_index == f.index && stamp_text == f.stamp_text; }
  cv::Mat DynamicMask() const;   // CV_8U, 255 = a pixel of an instance voted dynamic
};
constexpr const char* kBoardKey = "epi.board";

class VoteStage : public Stage {
 public:
  VoteStage(const ParamMap& p, std::shared_ptr<Blackboard> board);
  std::string name() const override { return "epi.vote"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override;
  void Finish(RunEnd& end) override { tally_.Report(end); }

 private:
  geometry::DynamicMaskOptions mask_;
  geometry::LkOptions lk_;
  geometry::RigidRansacOptions pose_;
  MaskVoteOptions vote_;
  Rng rng_;
  std::shared_ptr<Blackboard> board_;
  DetectionTally tally_;  // dynamic-class instances seen / dropped by min_confidence (issue 39)
};

class NerfModule : public MapModule {
 public:
  NerfModule(const ParamMap& p, std::shared_ptr<Blackboard> board);
  std::string name() const override { return "epi.nerf"; }
  void OnKeyFrame(const MapModuleContext& ctx) override;
  void OnMapUpdate(const MapModuleContext& ctx) override;  // forgets culled keyframes
  // Writes RUN/nerf/: images/, masks/, sparse_points.ply, transforms.json (last, atomically).
  void Finish(const Map& map, RunEnd& end) override;

 private:
  struct Keyframe {
    std::string stamp_text;
    cv::Mat rgb;                      // BGR as read
    cv::Mat dynamic_mask;             // CV_8U 255 = dynamic (empty: none)
    std::vector<cv::Point2f> raw, un;  // keypoints no stage excluded (raw and undistorted pixels)
    cv::Mat descriptors;              // their rows
    std::vector<int> features;        // their feature indices in the keyframe's frame (trace ids)
    int frame_index = -1;
  };
  // The run's trace (the writer outlives Finish); set by OnKeyFrame. epi.nerf traces its matches
  // and gates at Finish (README "Trace").
  trace::TraceWriter* trace_ = nullptr;
  std::shared_ptr<Blackboard> board_;
  TriangulationGates gates_;
  features::Mnn2Options match_;
  std::map<int64_t, Keyframe> keyframes_;  // by keyframe id (creation order)
  Camera camera_;
};

}  // namespace dynref::epi
