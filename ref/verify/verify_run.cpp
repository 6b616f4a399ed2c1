#include "verify/verify_run.h"

#include "core/format.h"

namespace dynref::verify {
namespace {

bool Verifiable(const trace::Record& r) {
  return r.type == trace::RecordType::kProbability || r.type == trace::RecordType::kDecision ||
         r.type == trace::RecordType::kResidual;
}

std::string Describe(const trace::Record& r, const Verdict& v) {
  const std::string where = " frame " + std::to_string(r.frame) + " " + trace::RecordTypeName(r.type) + " " +
                            r.stage + " " + r.entity;
  if (v.status == Status::kMismatch) return "mismatch" + where + " field " + v.field + ": " + v.detail;
  return "unverifiable" + where + ": " + v.detail;
}

}  // namespace

std::string ReportStage(const trace::Record& r) {
  if (r.type != trace::RecordType::kResidual) return r.stage;
  const size_t hash = r.stage.find('#');
  return hash == std::string::npos ? r.stage : r.stage.substr(0, hash);
}

VerifyReport VerifyTrace(const TraceModel& trace, const VerifierList& verifiers, const VerifyOptions& options) {
  VerifyReport report;
  for (size_t fp = 0; fp < trace.frames().size(); ++fp) {
    const FrameRecords& fr = trace.frames()[fp];
    if (options.first_frame && fr.frame < *options.first_frame) continue;
    if (options.last_frame && fr.frame > *options.last_frame) continue;
    for (size_t i = 0; i < fr.records.size(); ++i) {
      const trace::Record& r = fr.records[i];
      if (!Verifiable(r)) continue;
      const std::string stage = ReportStage(r);
      if (!options.stage.empty() && stage != options.stage) continue;
      Check check;
      const Verifier* claimant = nullptr;
      for (const auto& v : verifiers)
        if (v->Claims(r)) {
          claimant = v.get();
          break;
        }
      if (claimant == nullptr)
        check.NoVerifier(std::string("no verifier for ") + trace::RecordTypeName(r.type) + " records of stage '" + stage + "'");
      else
        claimant->Verify(trace, RecordRef{fp, i}, check);
      StageReport& s = report.stages[stage];
      const Verdict& v = check.verdict();
      if (v.status == Status::kVerified) {
        ++s.verified, ++report.verified;
        continue;
      }
      if (v.status == Status::kMismatch) ++s.mismatched, ++report.mismatched;
      else ++s.unverifiable, ++report.unverifiable;
      if (static_cast<int>(s.examples.size()) < options.max_examples) s.examples.push_back(Describe(r, v));
    }
  }
  return report;
}

void WriteVerifyReport(const VerifyReport& report, const TraceModel& trace, std::ostream& out) {
  out << "trace " << trace.path() << " (schema " << trace.schema_version() << ", method "
      << trace.HeaderValue("method") << ")\n";
  out << "stage,verified,mismatched,unverifiable\n";
  for (const auto& [stage, s] : report.stages)
    out << stage << "," << s.verified << "," << s.mismatched << "," << s.unverifiable << "\n";
  out << "total," << report.verified << "," << report.mismatched << "," << report.unverifiable << "\n";
  for (const auto& [stage, s] : report.stages)
    for (const std::string& e : s.examples) out << "  " << e << "\n";
  out << (report.ok() ? "verified: every record recomputed from the trace\n"
                      : "NOT verified: " + std::to_string(report.mismatched) + " mismatched, " +
                            std::to_string(report.unverifiable) + " unverifiable\n");
}

}  // namespace dynref::verify
