#include "dynamic/sgdo/register.h"

#include "dynamic/sgdo/stages.h"

namespace dynref {

void RegisterSgdoStages(StageRegistry& registry) {
  // One blackboard per registry: the stages of one run share the current frame's mask.
  auto board = std::make_shared<sgdo::Blackboard>();
  registry.Register("sgdo.mask", [board](const ParamMap& p) -> std::unique_ptr<Stage> {
    return std::make_unique<sgdo::MaskStage>(p, board);
  });
  registry.Register("sgdo.coarse", [board](const ParamMap& p) -> std::unique_ptr<Stage> {
    return std::make_unique<sgdo::CoarseStage>(p, board);
  });
  registry.Register("sgdo.depth", [](const ParamMap& p) -> std::unique_ptr<Stage> {
    return std::make_unique<sgdo::DepthStage>(p);
  });
  registry.Register("sgdo.densemap", [board](const ParamMap& p) -> std::unique_ptr<Stage> {
    return std::make_unique<sgdo::DenseMapStage>(p, board);
  });
}

}  // namespace dynref
