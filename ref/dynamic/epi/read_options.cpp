// Parameter specs of epi.enhance, epi.vote and epi.nerf (read_options.h). The butterfly search's
// cost grows with population x iterations: at most 1000 x 10000. `down` >= kMinEnhanceDown keeps
// the two-scale image at least 2 px on each side of the smallest frame `dynref run` accepts
// (64x48: 48 x 0.05 = 2.4); 1e-308 made cv::resize assert on frame 0 (scripts/fuzz.sh configs).
// The LK keys of epi.vote as geometry::LkOptions::Check needs them (odd window, border >= 1).
#include "dynamic/epi/read_options.h"

#include "dynamic/epi/enhance.h"

namespace dynref {

void RegisterEpiParams(MethodRegistry& registry) {
  registry.AddParams(
      "epi.enhance",
      {{BelowHi(Real("s", 0, 0.5)), OddInteger("window", 3, 101), Real("alpha", 0, 100), RealAbove("p", 0, 100),
        RealAbove("e0", 0, 1), BelowHi(Real("down", epi::kMinEnhanceDown, 1)), Real("w_ms", 0, 1), RealAbove("clahe_clip", 0, 100),
        Integer("clahe_tiles", 1, 64), RealAbove("edge_threshold", 0, 10), Flag("optimise"),
        Integer("boa_population", 3, 1000), Integer("boa_iterations", 1, 10000), Real("boa_switch_p", 0, 1),
        RealAbove("boa_sensory_c", 0, 10), Real("boa_power_a", 0, 1), Real("boa_cauchy_scale", 0, 10),
        RealAbove("alpha_max", 0, 100), RealAbove("p_min", 0, 100), RealAbove("p_max", 0, 100), Seed("seed")},
       {{"p_min", "p_max"}}});
  registry.AddParams(
      "epi.vote",
      {{Names("dynamic_classes"), Real("min_confidence", 0, 1), Choice("threshold_scale", {"detector", "raw"}),
        RealAbove("epi_threshold_px", 0, 100),
        BelowHi(Real("vote_ratio", 0, 1)), OddInteger("lk_window_px", 3, 101), Integer("lk_max_level", 0, 10),
        Integer("border_px", 1, 1000), Real("patch_sad_max", 0, 1e7), RealAbove("pose_inlier_px", 0, 100),
        Integer("pose_iterations", 1, 100000), Integer("pose_min_inliers", 1, 100000), Seed("ransac_seed")}});
  registry.AddParams("epi.nerf", {{BelowHi(RealAbove("parallax_cos_max", 0, 1)), RealAbove("reprojection_px", 0, 100),
                                   RealAbove("mnn_ratio", 0, 1)}});
}

}  // namespace dynref
