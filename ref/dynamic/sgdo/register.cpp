#include "dynamic/sgdo/register.h"
#include "dynamic/sgdo/read_options.h"

#include "dynamic/sgdo/stages.h"

namespace dynref {

void RegisterSgdoMethod(MethodRegistry& registry) {
  RegisterSgdoParams(registry);  // keys and ranges, checked before any component is built
  // The components of one run share the current frame's mask through the run's SharedState.
  registry.AddStage("sgdo.mask", [](const ParamMap& p, SharedState& shared) -> std::unique_ptr<Stage> {
    return std::make_unique<sgdo::MaskStage>(p, shared.Get<sgdo::Blackboard>(sgdo::kBoardKey));
  });
  registry.AddStage("sgdo.coarse", [](const ParamMap& p, SharedState& shared) -> std::unique_ptr<Stage> {
    return std::make_unique<sgdo::CoarseStage>(p, shared.Get<sgdo::Blackboard>(sgdo::kBoardKey));
  });
  registry.AddStage("sgdo.depth", [](const ParamMap& p, SharedState&) -> std::unique_ptr<Stage> {
    return std::make_unique<sgdo::DepthStage>(p);
  });
  registry.AddMapModule("sgdo.densemap", [](const ParamMap& p, SharedState& shared) -> std::unique_ptr<MapModule> {
    return std::make_unique<sgdo::DenseMapModule>(p, shared.Get<sgdo::Blackboard>(sgdo::kBoardKey));
  });
}

}  // namespace dynref
