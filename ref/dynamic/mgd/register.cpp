#include "dynamic/mgd/register.h"
#include "dynamic/mgd/read_options.h"

#include "dynamic/mgd/stages.h"

namespace dynref {

void RegisterMgdMethod(MethodRegistry& registry) {
  RegisterMgdParams(registry);  // keys and ranges, checked before any component is built
  registry.AddStage("mgd.boxes", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<Stage> {
    p.RequireKnownKeys({});  // options live in mgd.probability
    return std::make_unique<mgd::BoxStage>(s.Get<mgd::MgdState>(mgd::kStateKey));
  });
  registry.AddStage("mgd.probability", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<Stage> {
    return std::make_unique<mgd::ProbabilityStage>(mgd::ReadOptions(p), s.Get<mgd::MgdState>(mgd::kStateKey));
  });
  registry.AddStage("mgd.reprojection", [](const ParamMap& p, SharedState& s) -> std::unique_ptr<Stage> {
    p.RequireKnownKeys({});
    return std::make_unique<mgd::ReprojectionStage>(s.Get<mgd::MgdState>(mgd::kStateKey));
  });
}

}  // namespace dynref
