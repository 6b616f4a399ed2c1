// Parameter specs of semantic.mask and semantic.map (read_options.h). Sizes of voxels, octree
// cells and grid cells >= 1 mm / 5 mm (memory grows with the inverse square or cube) and <= 1 m
// (a coarser map is not a map: grid_cell_m = 1e308 gave a 2 x 1 grid, issue 37).
#include "dynamic/semantic/read_options.h"

namespace dynref {

void RegisterSemanticParams(MethodRegistry& registry) {
  registry.AddParams("semantic.mask",
                     {{Names("prior_dynamic_classes"), Real("min_confidence", 0, 1),
                       Choice("threshold_scale", {"detector", "raw"}), Integer("d_max_px", 1, 50),
                       RealAbove("t_int_m", 0, 10), Flag("interaction"), OddInteger("dilation_kernel_px", 1, 101),
                       Flag("reject_keypoints")}});
  registry.AddParams(
      "semantic.map",
      {{Real("min_depth_m", 0, 100), RealAbove("max_depth_m", 0, 100), Integer("pixel_stride", 1, 64),
        Real("keyframe_leaf_m", 0.001, 1), Real("semantic_alpha", 0, 1), Integer("sor_k", 1, 1000),
        RealAbove("sor_std_mult", 0, 100), Real("voxel_leaf_m", 0.001, 1), Real("octree_resolution_m", 0.001, 1),
        Real("grid_cell_m", 0.005, 1), Real("grid_h_min_m", -10, 10), Real("grid_h_max_m", -10, 10), Seed("floor_seed"),
        Flag("remove_dynamic"), Flag("write_intermediate"), Text("output_prefix")},
       {{"min_depth_m", "max_depth_m"}, {"grid_h_min_m", "grid_h_max_m"}}});
  registry.AddRequirement("semantic.map", "semantic.mask");
}

}  // namespace dynref
