// Motion-blur SLAM (seed 003): registers blur.mask and blur.probability (components.h).
#include "dynamic/blur/components.h"
#include "dynamic/blur/read_options.h"
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
}

}  // namespace dynref
