// Enhanced-epipolar SLAM (seed 004): registers epi.enhance, epi.vote and epi.nerf (stages.h).
#include "dynamic/epi/stages.h"
#include "dynamic/epi/read_options.h"
#include "method/registry.h"

namespace dynref {

void RegisterEpiMethod(MethodRegistry& registry) {
  RegisterEpiParams(registry);  // keys and ranges, checked before any component is built
  registry.AddStage("epi.enhance", [](const ParamMap& p, SharedState&) -> std::unique_ptr<Stage> {
    return std::make_unique<epi::EnhanceStage>(p);
  });
  registry.AddStage("epi.vote", [](const ParamMap& p, SharedState& shared) -> std::unique_ptr<Stage> {
    return std::make_unique<epi::VoteStage>(p, shared.Get<epi::Blackboard>(epi::kBoardKey));
  });
  registry.AddMapModule("epi.nerf", [](const ParamMap& p, SharedState& shared) -> std::unique_ptr<MapModule> {
    return std::make_unique<epi::NerfModule>(p, shared.Get<epi::Blackboard>(epi::kBoardKey));
  });
}

}  // namespace dynref
