// The registry of every method's stages (one registration call per method) and stage creation
// from a MethodConfig.
#pragma once
#include <memory>
#include <vector>

#include "pipeline/method_config.h"
#include "pipeline/stage.h"

namespace dynref {

// Registry with every built-in method's stages.
StageRegistry& BuiltinStageRegistry();
// Creates the stages of cfg in config order; InputError (file:line) for an unknown stage name.
std::vector<std::unique_ptr<Stage>> CreateStages(const MethodConfig& cfg, const StageRegistry& registry);

}  // namespace dynref
