// Parameter specs of sgdo.mask, sgdo.coarse, sgdo.depth and sgdo.densemap (read_options.h).
// Upper bounds: far above any value a paper or config uses, and where cost or memory grows with
// the value (leaf sizes down, margins up), where the run would still finish in seconds. The LK
// keys as geometry::LkOptions::Check needs them (odd window, border >= 1 for the 3x3 patch): an
// even window or border 0 passed here and failed at the stage's line (scripts/fuzz.sh configs).
#include "dynamic/sgdo/read_options.h"

#include "dynamic/common/dense_map_module.h"

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
  dynamic_common::RegisterDenseMapParams(registry, "sgdo.densemap", "sgdo.mask");
}

}  // namespace dynref
