// Verifiers of the epi records (ref/verify/README.md).
#include "verify/verifier.h"

namespace dynref::verify {

void AddEpiVerifiers(VerifierList& out) { (void)out; }

}  // namespace dynref::verify
