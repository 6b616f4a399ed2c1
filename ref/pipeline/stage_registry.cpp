// One registration call per method (each method's register.h).
#include "pipeline/stage_registry.h"

#include "core/error.h"
#include "dynamic/sgdo/register.h"

namespace dynref {

StageRegistry& BuiltinStageRegistry() {
  static StageRegistry* registry = [] {
    auto* r = new StageRegistry();
    RegisterSgdoStages(*r);  // seed 001
    return r;
  }();
  return *registry;
}

std::vector<std::unique_ptr<Stage>> CreateStages(const MethodConfig& cfg, const StageRegistry& registry) {
  std::vector<std::unique_ptr<Stage>> out;
  for (const StageConfig& sc : cfg.stages) {
    const StageFactory* f = registry.Find(sc.name);
    if (f == nullptr) {
      std::string known;
      for (const std::string& n : registry.Names()) known += (known.empty() ? "" : ", ") + n;
      throw InputError(cfg.path, sc.params.line,
                       "unknown stage '" + sc.name + "' (known: " + (known.empty() ? "none" : known) + ")");
    }
    out.push_back((*f)(sc.params));
  }
  return out;
}

}  // namespace dynref
