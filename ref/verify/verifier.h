// One kind of record a verifier recomputes (ref/verify/README.md lists every verifier with the
// paper equation it implements and its tolerance). A verifier is written from the papers'
// equations and ref/trace/README.md, never by calling the stage code: that independence is the
// point of `dynref trace verify`.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "verify/check.h"
#include "verify/trace_model.h"

namespace dynref::verify {

class Verifier {
 public:
  virtual ~Verifier() = default;
  // Whether this verifier recomputes record r (a PROB, DECISION or RESIDUAL record).
  virtual bool Claims(const trace::Record& r) const = 0;
  // Recomputes what `at` claims from the trace; reports through `check`.
  virtual void Verify(const TraceModel& trace, RecordRef at, Check& check) const = 0;
};

using VerifierList = std::vector<std::unique_ptr<Verifier>>;

// Each family adds its verifiers (one file per family, verify_<family>.cpp).
void AddBackboneVerifiers(VerifierList& out);   // residuals and their links, keyframes, structure
void AddMgdVerifiers(VerifierList& out);
void AddBlurVerifiers(VerifierList& out);
void AddEpiVerifiers(VerifierList& out);
void AddSgdoVerifiers(VerifierList& out);
void AddSemanticVerifiers(VerifierList& out);
void AddLoopVerifiers(VerifierList& out);      // loop closing (issue 34)
// All of them, in this order (the first verifier that claims a record verifies it).
VerifierList AllVerifiers();

}  // namespace dynref::verify
