// `dynref diff`: key-matched comparison of two traces in processing order (README "Diff").
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace dynref::trace {

struct DiffOptions {
  double abs_tol = 0.0;  // float fields pass if |a-b| <= abs_tol ...
  double rel_tol = 0.0;  // ... or |a-b| <= rel_tol * max(|a|,|b|)
  // Per-field absolute tolerance overriding abs_tol; key = field name ("after", "u") or its base
  // name without an index ("start" matches "start[1]", "T_wc" matches "T_wc[3]").
  std::map<std::string, double> field_abs_tol;
  int max_report = 20;   // divergences listed in the report (the first one is always shown)
  // --summary: how far the candidate strays (issue 18, a faster variant against the oracle):
  // deviation of the final poses and distributions of the probability differences per stage.
  bool summary = false;
  void Check() const;    // InputError naming the bad field
  // Parses "FIELD=X" into field_abs_tol (InputError on a bad spec).
  void AddFieldTolerance(const std::string& spec);
};

enum class DivergenceKind { kDiffer, kMissing, kExtra };

struct Divergence {
  DivergenceKind kind = DivergenceKind::kDiffer;
  int64_t frame = -1;
  double position = 0;  // processing position within the frame (golden order)
  std::string type, stage, entity_kind, entity;
  int occurrence = 0;
  std::string field;     // kDiffer: the first differing field
  std::string expected, actual, tolerance;
  std::string Describe() const;  // one line
};

struct StageCounts {
  uint64_t golden = 0, candidate = 0, differ = 0, missing = 0, extra = 0;
};
struct FieldError {
  double max_abs = 0, max_rel = 0;
  int64_t max_abs_frame = -1;
  std::string max_abs_entity;
  uint64_t compared = 0;
};

struct DiffResult {
  std::vector<Divergence> divergences;  // first max_report in processing order
  uint64_t total_divergences = 0;
  std::map<std::string, StageCounts> stages;      // stage label -> counts
  std::map<std::string, FieldError> field_errors;  // float field -> largest errors
  std::vector<std::string> notes;                  // header/footer differences
  // For the summary, over matched records: final pose deviation per frame (translation in m,
  // rotation in degrees) and |after_golden - after_candidate| of PROB records per stage.
  std::vector<int64_t> pose_frames;
  std::vector<double> pose_trans_m, pose_rot_deg;
  std::map<std::string, std::vector<double>> prob_after_diff;
  bool footer_differs = false;
  int ExitCode() const { return total_divergences == 0 && !footer_differs ? 0 : 1; }
  std::string Report(const std::string& golden, const std::string& candidate,
                     const DiffOptions& options) const;
};

// Compares two trace files (TraceError when either is unreadable/truncated/other version).
DiffResult DiffTraces(const std::string& golden_path, const std::string& candidate_path,
                      const DiffOptions& options);

}  // namespace dynref::trace
