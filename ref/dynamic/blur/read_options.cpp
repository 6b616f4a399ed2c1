// Parameter specs of blur.mask, blur.probability and blur.densemap (read_options.h).
#include "dynamic/blur/read_options.h"

#include "dynamic/common/dense_map_module.h"

namespace dynref {

void RegisterBlurParams(MethodRegistry& registry) {
  registry.AddParams(
      "blur.mask",
      {{Names("person_classes"), Real("min_confidence", 0, 1), Choice("threshold_scale", {"detector", "raw"}), Flag("compensation"), RealAbove("r_threshold", 0, 1),
        Integer("history", 1, 30), RealAbove("iou_found", 0, 1), Integer("max_consecutive", 1, 1000),
        Flag("depth_fusion"), Integer("grid_cols", 1, 256), Integer("grid_rows", 1, 256),
        Integer("samples_per_cell", 1, 100), RealAbove("alpha_m", 0, 10), RealAbove("sigma_mult", 0, 100),
        Integer("dilation_size", 0, 100), Seed("sampling_seed"), Flag("write_mask_layers")}});
  registry.AddParams("blur.probability", {{Flag("compute"), RealAbove("radius_px", 0, 1000), Real("c1", 0, 1000),
                                           Real("c2", 0, 1000), BelowHi(Real("theta", 0, 1))}});
  registry.AddRequirement("blur.probability", "blur.mask");
  dynamic_common::RegisterDenseMapParams(registry, "blur.densemap", "blur.mask");
}

}  // namespace dynref
