// Verifiers of the semantic records (ref/verify/README.md).
#include "verify/verifier.h"

namespace dynref::verify {

void AddSemanticVerifiers(VerifierList& out) { (void)out; }

}  // namespace dynref::verify
