#include "dynamic/sgdo/register.h"
#include "dynamic/sgdo/read_options.h"

#include "dynamic/common/dense_map_module.h"
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
  // Sec. 3.6: pixels outside M (the dilated instance masks), static objects coloured by class.
  registry.AddMapModule("sgdo.densemap", [](const ParamMap& p, SharedState& shared) -> std::unique_ptr<MapModule> {
    std::shared_ptr<sgdo::Blackboard> board = shared.Get<sgdo::Blackboard>(sgdo::kBoardKey);
    return std::make_unique<dynamic_common::DenseMapModule>(
        "sgdo.densemap", "dynref sgdo dense static map (seed 001 Sec. 3.6)", p, [board](const Frame& f) {
          if (!board->Has(f)) throw std::logic_error("sgdo.densemap needs sgdo.mask earlier in the stage list");
          return dynamic_common::KeyframeMasks{board->mask.mask, board->static_labels};
        });
  });
}

}  // namespace dynref
