// Verifiers of the backbone records (ref/verify/README.md).
#include "verify/verifier.h"

namespace dynref::verify {

void AddBackboneVerifiers(VerifierList& out) { (void)out; }

}  // namespace dynref::verify
