#include "verify/verifier.h"

namespace dynref::verify {

VerifierList AllVerifiers() {
  VerifierList out;
  AddBackboneVerifiers(out);
  AddMgdVerifiers(out);
  AddBlurVerifiers(out);
  AddEpiVerifiers(out);
  AddSgdoVerifiers(out);
  AddSemanticVerifiers(out);
  AddLoopVerifiers(out);
  return out;
}

}  // namespace dynref::verify
