// Verifiers of the blur records (ref/verify/README.md).
#include "verify/verifier.h"

namespace dynref::verify {

void AddBlurVerifiers(VerifierList& out) { (void)out; }

}  // namespace dynref::verify
