// `dynref reproduce claims`: resolves every claim of the registry (claims.h) against the committed
// reports and the papers' tables, computes its verdict and writes the ledger reports/CLAIMS.md.
#pragma once
#include <string>
#include <vector>

#include "reproduce/claims.h"
#include "reproduce/report_reader.h"

namespace dynref::reproduce {

struct ResolvedOperand {
  std::string label;
  ReportValue ours;
  std::string report;         // "sgdo-table6.md"
  std::string report_commit;  // the commit that wrote the report ("Written by ... commit X")
  std::string report_runs;    // "seeds 1,2,3, 300 frames"
  double paper = 0.0;
  std::string paper_text;  // the paper's cell as printed in its CSV
  bool has_paper = false;
};

struct ClaimResult {
  Claim claim;
  std::vector<ResolvedOperand> operands;
  Measured derived;        // kImprovement: the per-seed improvement
  double threshold = 0.0;  // resolved (kAtLeast / kAtMost / kImprovement)
  Verdict verdict = Verdict::kNotMeasured;
  std::string runs;  // "seeds 1,2,3, 300 frames" of the first operand's report
};

// Every claim resolved against `reports_dir` (reports/*.md) and `reports_dir`/paper-tables/*.csv.
// InputError (file:line) when a named report, heading, row, column or paper cell is missing.
std::vector<ClaimResult> ResolveClaims(const std::vector<Claim>& claims, const std::string& reports_dir);
// The verdict of one claim from its resolved numbers (kNotMeasured when a cell says "-" etc.).
Verdict ClaimVerdict(const ClaimResult& r);

struct ClaimsArgs {
  std::string out = "reports/CLAIMS.md";
  std::string reports = "reports";
};

// The ledger's Markdown; `link_prefix` is prepended to report file names in links ("" when the
// ledger sits beside the reports).
std::string ClaimsLedgerMarkdown(const std::vector<ClaimResult>& results, const std::string& link_prefix);
// Resolves AllClaims() under args.reports and writes args.out atomically; returns kExitOk.
int RunClaimsLedger(const ClaimsArgs& args);

}  // namespace dynref::reproduce
