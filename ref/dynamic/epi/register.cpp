// Enhanced-epipolar SLAM (seed 004): registers epi.enhance and epi.vote (stages.h).
#include "dynamic/epi/stages.h"
#include "method/registry.h"

namespace dynref {

void RegisterEpiMethod(MethodRegistry& registry) {
  registry.AddStage("epi.enhance", [](const ParamMap& p, SharedState&) -> std::unique_ptr<Stage> {
    return std::make_unique<epi::EnhanceStage>(p);
  });
  registry.AddStage("epi.vote", [](const ParamMap& p, SharedState&) -> std::unique_ptr<Stage> {
    return std::make_unique<epi::VoteStage>(p);
  });
}

}  // namespace dynref
