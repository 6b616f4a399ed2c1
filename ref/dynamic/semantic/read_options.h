// The declared keys and ranges of the semantic components' parameters (method/params.h ParamSpec),
// checked by the run's Session before any component is built (issue 33 part 2, issue 37).
#pragma once
#include "method/registry.h"

namespace dynref {
void RegisterSemanticParams(MethodRegistry& registry);
}  // namespace dynref
