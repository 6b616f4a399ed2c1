// Motion-blur SLAM (seed 003): registers blur.mask and blur.probability (components.h) and the
// dense map blur.densemap (dynamic/common/dense_map_module.h).
#include "dynamic/blur/components.h"
#include "dynamic/blur/read_options.h"
#include "dynamic/common/dense_map_module.h"
#include "method/registry.h"

namespace dynref {

void RegisterBlurMethod(MethodRegistry& registry) {
  RegisterBlurParams(registry);  // keys and ranges, checked before any component is built
  registry.AddStage("blur.mask", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<Stage> {
    return std::make_unique<blur::MaskStage>(p, s.Get<blur::Board>(blur::kBoardKey));
  });
  registry.AddStage("blur.probability", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<Stage> {
    return std::make_unique<blur::ProbabilityStage>(p, s.Get<blur::Board>(blur::kBoardKey));
  });
  // Sec. 4.4 (spec 003 step 7): the keyframe pixels outside the final dilated mask M_sd.
  registry.AddMapModule("blur.densemap", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<MapModule> {
    std::shared_ptr<blur::Board> board = s.Get<blur::Board>(blur::kBoardKey);
    return std::make_unique<dynamic_common::DenseMapModule>(
        "blur.densemap", "dynref blur dense static map (seed 003 Sec. 4.4)", p, [board](const Frame& f) {
          if (!board->Has(f)) throw std::logic_error("blur.densemap needs blur.mask earlier in the stage list");
          return dynamic_common::KeyframeMasks{board->mask, cv::Mat()};
        });
  });
}

}  // namespace dynref
