// The verdict on one record (`dynref trace verify`): verified, a mismatch between what the record
// claims and what the verifier recomputed from the trace, or unverifiable because an input the
// recomputation needs is not in the trace. A verifier reports through a Check.
#pragma once
#include <optional>
#include <string>

#include "trace/trace_reader.h"

namespace dynref::verify {

enum class Status { kVerified, kMismatch, kUnverifiable };

struct Verdict {
  Status status = Status::kVerified;
  std::string field;      // the first field that did not agree, or the missing input
  double expected = 0;    // recomputed value (mismatch)
  double recorded = 0;    // value in the record (mismatch)
  std::string detail;     // text form (exact fields, or what is missing)
};

// Relative-or-absolute tolerance of float comparisons: |e - r| <= tol * max(1, |e|, |r|).
// Both NaN agree; an infinity agrees only with the same infinity.
bool Agrees(double expected, double recorded, double tol);

class Check {
 public:
  // Compares one float field (first disagreement wins; later calls are ignored once decided).
  void Near(const std::string& field, double expected, double recorded, double tol = 1e-9);
  // Compares an exact field (decision kept, reason, ids).
  void Same(const std::string& field, const std::string& expected, const std::string& recorded);
  void Same(const std::string& field, bool expected, bool recorded);
  // An input of the recomputation is not in the trace: the record is unverifiable.
  void Missing(const std::string& what);
  // No verifier claims the record (unverifiable, `why` says so).
  void NoVerifier(const std::string& why);
  // A named input of `r`; marks it missing when absent (then returns NaN).
  double Need(const trace::Record& r, const std::string& name);
  // Like Need for a value found elsewhere (another record, the config).
  double Need(const std::optional<double>& value, const std::string& what);
  bool ok() const { return verdict_.status == Status::kVerified; }
  const Verdict& verdict() const { return verdict_; }

 private:
  Verdict verdict_;
};

}  // namespace dynref::verify
