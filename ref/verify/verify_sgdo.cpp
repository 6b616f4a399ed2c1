// Verifiers of the sgdo records (ref/verify/README.md).
#include "verify/verifier.h"

namespace dynref::verify {

void AddSgdoVerifiers(VerifierList& out) { (void)out; }

}  // namespace dynref::verify
