// The declared keys and ranges of the sgdo components' parameters (method/params.h ParamSpec),
// checked by the run's Session before any component is built (issue 33 part 2, issue 37).
#pragma once
#include "method/registry.h"

namespace dynref {
void RegisterSgdoParams(MethodRegistry& registry);
}  // namespace dynref
