// `dynref trace verify RUN|TRACE [--stage S] [--frames A-B]`: every PROB, DECISION and RESIDUAL
// record recomputed by the verifier that claims it; per-stage counts of verified, mismatching
// and unverifiable records with the first few of each.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "verify/verifier.h"

namespace dynref::verify {

struct VerifyOptions {
  std::string stage;              // only records of this stage / optimiser call family ("" = all)
  std::optional<int64_t> first_frame, last_frame;
  int max_examples = 3;           // examples listed per stage and status
};

struct StageReport {
  int64_t verified = 0, mismatched = 0, unverifiable = 0;
  std::vector<std::string> examples;  // first mismatches / unverifiable records, as text
};

struct VerifyReport {
  std::map<std::string, StageReport> stages;  // by stage name (call ids without "#N")
  int64_t verified = 0, mismatched = 0, unverifiable = 0;
  bool ok() const { return mismatched == 0 && unverifiable == 0; }
};

// Stage name a report row is filed under: the stage, or a residual's call id without "#N".
std::string ReportStage(const trace::Record& r);
VerifyReport VerifyTrace(const TraceModel& trace, const VerifierList& verifiers, const VerifyOptions& options);
void WriteVerifyReport(const VerifyReport& report, const TraceModel& trace, std::ostream& out);

}  // namespace dynref::verify
