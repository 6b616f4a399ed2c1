// Verifiers of the mgd records (ref/verify/README.md).
#include "verify/verifier.h"

namespace dynref::verify {

void AddMgdVerifiers(VerifierList& out) { (void)out; }

}  // namespace dynref::verify
