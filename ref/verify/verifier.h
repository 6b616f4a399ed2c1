// One kind of record a verifier recomputes (ref/verify/README.md lists every verifier with the
// paper equation it implements and its tolerance). A verifier is written from the papers'
// equations and ref/trace/README.md, never by calling the stage code: that independence is the
// point of `dynref trace verify`.
#pragma once
#include <functional>
#include <limits>
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

// Absolute tolerance of a value the verifier recomputes with the stage's own double arithmetic
// (ref/verify/README.md); a verifier with a looser bound names its own constant and says why.
inline constexpr double kTol = 1e-9;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// One verifier per (record type, stage); the function branches on the entity kind.
class StageVerifier : public Verifier {
 public:
  using Fn = std::function<void(const TraceModel&, RecordRef, Check&)>;
  StageVerifier(trace::RecordType type, std::string stage, Fn fn)
      : type_(type), stage_(std::move(stage)), fn_(std::move(fn)) {}
  bool Claims(const trace::Record& r) const override { return r.type == type_ && r.stage == stage_; }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override { fn_(t, at, c); }

 private:
  trace::RecordType type_;
  std::string stage_;
  Fn fn_;
};

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
