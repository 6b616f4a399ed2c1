// Semantic mapping (seed 002) components; see register.h and README.md.
#pragma once
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "dense/dense_map.h"
#include "dynamic/semantic/interaction.h"
#include "io/mask_format.h"
#include "dense/occupancy_grid.h"
#include "geometry/dynamic_mask.h"
#include "method/detection_tally.h"
#include "method/map_module.h"
#include "method/params.h"
#include "method/stage.h"

namespace dynref::semantic {

constexpr const char* kBoardKey = "semantic.board";

// The current frame's dynamic mask (prior dynamic + non-prior dynamic instances) and the class
// labels of the remaining (static) recognised objects, written by semantic.mask.
struct Board {
  int frame = -1;
  std::string stamp;
  geometry::DynamicMask dynamic;
  cv::Mat static_classes;  // CV_16S COCO class per pixel of a static instance, -1 none
  bool Has(const Frame& f) const { return frame == f.index && stamp == f.stamp_text; }
};

struct MaskOptions {
  std::set<int> prior_dynamic_class_ids;  // Table 1: person and animals
  double min_confidence = 0.25;
  int d_max_px = 6;
  double t_int_m = 0.3;
  bool interaction = true;        // off = only prior-dynamic masks removed (implicit ablation)
  int dilation_kernel_px = 1;
  bool reject_keypoints = true;
  void Check() const;
};

// semantic.mask's options from its config parameters (InputError naming file:line).
MaskOptions MaskOptionsFromParams(const ParamMap& p);

// Sec. 3.1-3.2 on one frame: the detected instances by class partition and interaction test.
struct InstanceClasses {
  std::set<int> prior_dynamic, prior_static, non_prior_dynamic;  // detection instance ids
  struct Test {
    int a = 0, b = 0;  // prior-dynamic instance a against prior-static instance b
    InteractionResult result;
  };
  std::vector<Test> tests;  // in evaluation order (b ascending, then a ascending; b stops at its first hit)
};
InstanceClasses ClassifyInstances(const FrameDetections& det, const cv::Mat& depth_m, const MaskOptions& o);

class MaskStage : public Stage {
 public:
  MaskStage(const ParamMap& p, std::shared_ptr<Board> board);
  std::string name() const override { return "semantic.mask"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override;
  void Finish(RunEnd& end) override { tally_.Report(end); }

 private:
  MaskOptions o_;
  std::shared_ptr<Board> board_;
  DetectionTally tally_;  // prior-dynamic instances seen / dropped by min_confidence (issue 39)
};

struct MapOptions {
  dense::DenseMapOptions backproject;  // depth range, pixel stride (colour_by_class unused)
  double keyframe_leaf_m = 0.01;
  double semantic_alpha = 0.5;
  dense::SorOptions sor;
  double voxel_leaf_m = 0.01;
  double octree_resolution_m = 0.05;
  dense::GridOptions grid;
  dense::FloorOptions floor;
  bool remove_dynamic = true;      // false: the same map without removal (the orb baseline)
  bool write_intermediate = true;  // the raw and SOR clouds as PCD (file-size table)
  std::string prefix = "semantic_map";
  void Check() const;
};

class MapModule : public dynref::MapModule {
 public:
  MapModule(const ParamMap& p, std::shared_ptr<Board> board);
  std::string name() const override { return "semantic.map"; }
  void OnKeyFrame(const MapModuleContext& ctx) override;
  // Drops the clouds of keyframes local mapping culled (redundant by ORB-SLAM2's 90 % rule).
  void OnMapUpdate(const MapModuleContext& ctx) override;
  void Finish(const Map& map, RunEnd& end) override;

 private:
  MapOptions o_;
  std::shared_ptr<Board> board_;
  std::map<int64_t, dense::PointCloud> keyframe_clouds_;  // camera frame, by keyframe id
  cv::Mat rays_;  // UndistortedRays of the run's camera (empty: no distortion)
  bool rays_ready_ = false;
};

}  // namespace dynref::semantic
