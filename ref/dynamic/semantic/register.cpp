#include "dynamic/semantic/register.h"
#include "dynamic/semantic/read_options.h"

#include "dynamic/semantic/components.h"

namespace dynref {

void RegisterSemanticMethod(MethodRegistry& registry) {
  RegisterSemanticParams(registry);  // keys and ranges, checked before any component is built
  registry.AddStage("semantic.mask", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<Stage> {
    return std::make_unique<semantic::MaskStage>(p, s.Get<semantic::Board>(semantic::kBoardKey));
  });
  registry.AddMapModule("semantic.map", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<MapModule> {
    return std::make_unique<semantic::MapModule>(p, s.Get<semantic::Board>(semantic::kBoardKey));
  });
}

}  // namespace dynref
