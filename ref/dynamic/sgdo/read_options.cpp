// Parameter specs of sgdo.mask, sgdo.coarse, sgdo.depth and sgdo.densemap (read_options.h).
// Upper bounds: far above any value a paper or config uses, and where cost or memory grows with
// the value (leaf sizes down, margins up), where the run would still finish in seconds. The LK
// keys as geometry::LkOptions::Check needs them (odd window, border >= 1 for the 3x3 patch): an
// even window or border 0 passed here and failed at the stage's line (scripts/fuzz.sh configs).
#include "dynamic/sgdo/read_options.h"

namespace dynref {

void RegisterSgdoParams(MethodRegistry& registry) {
  registry.AddParams("sgdo.mask", {{Names("dynamic_classes"), Real("min_confidence", 0, 1),
                                    Choice("threshold_scale", {"detector", "raw"}),
                                    OddInteger("dilation_kernel_px", 1, 101), Flag("reject_in_mask")}});
  registry.AddParams(
      "sgdo.coarse",
      {{Choice("combination", {"per_point", "instance_vote", "mask_only", "epipolar_only"}),
        RealAbove("th_epi_px", 0, 100), RealAbove("vote_ratio", 0, 1), OddInteger("lk_window_px", 3, 101),
        Integer("lk_max_level", 0, 10), Integer("lk_max_iterations", 1, 1000), RealAbove("lk_epsilon", 0, 1),
        Integer("border_px", 1, 1000), Real("patch_sad_max", 0, 1e7), RealAbove("ransac_threshold_px", 0, 100),
        RealAbove("ransac_confidence", 0, 1), Integer("ransac_max_iterations", 1, 100000), Seed("ransac_seed")}});
  // eta: relative depth residual; lambda: the weight's slope (0 = constant weight).
  registry.AddParams("sgdo.depth", {{RealAbove("eta", 0, 10), Real("lambda", 0, 1e6), Flag("reject"), Flag("weight")}});
  // Leaf sizes >= 1 mm (a voxel per pixel already below); the context margin's neighbour search
  // degenerates to all pairs as it grows (1.5 m: > 120 s for 2 frames, issue 37): at most 0.2 m.
  registry.AddParams(
      "sgdo.densemap",
      {{Real("keyframe_leaf_m", 0.001, 1), Real("global_leaf_m", 0.001, 1), Integer("filter_every_keyframes", 1, 100000),
        Choice("filter_mode", {"full", "incremental"}), RealAbove("context_margin_m", 0, 0.2), Integer("sor_k", 1, 1000),
        RealAbove("sor_std_mult", 0, 100), Real("min_depth_m", 0, 100), RealAbove("max_depth_m", 0, 100),
        Integer("pixel_stride", 1, 64), Flag("colour_by_class"), Text("output"), Choice("ply_format", {"binary", "ascii"})},
       {{"min_depth_m", "max_depth_m"}}});
  registry.AddRequirement("sgdo.densemap", "sgdo.mask");
}

}  // namespace dynref
