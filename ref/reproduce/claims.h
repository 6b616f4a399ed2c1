// The claims ledger (`dynref reproduce claims`, reports/CLAIMS.md): every relative claim of the five
// papers as data (claims_000.cpp .. claims_004.cpp, one file per paper), resolved against the
// committed reports' cells (report_reader.h) and the papers' tables (reports/paper-tables/*.csv),
// with a verdict computed from our means and S.D.s over seeds (claims_verdict.cpp).
#pragma once
#include <string>
#include <vector>

namespace dynref::reproduce {

// A cell of one of our reports: reports/<report>, the table under the heading that starts with
// `heading`, the row whose leading cells are `row` (" | "-joined), the column `column`.
struct ReportRef {
  std::string report;  // e.g. "sgdo-table6.md"
  std::string heading;
  std::string row;
  std::string column;
};

// A number of a paper's table: reports/paper-tables/<csv>, row = first cell, column = header name.
struct PaperRef {
  std::string csv;  // "" = none
  std::string row;
  std::string column;
};

// One side of a comparison: what it is called in the ledger, our cell, and the paper's value.
struct ClaimOperand {
  std::string label;
  ReportRef ours;
  PaperRef paper;
};

enum class ClaimKind {
  kLess,         // operands[0] < operands[1] (lower is better: ATE, RPE, ms)
  kGreater,      // operands[0] > operands[1] (higher is better: keypoints, precision)
  kNoWorse,      // operands[0] <= operands[1] (a change that must not hurt)
  kLowestOf,     // operands[0] below every other operand
  kAtLeast,      // operands[0] >= threshold
  kAtMost,       // operands[0] <= threshold
  kWithin,       // low <= operands[0] <= high
  kImprovement,  // per seed 100 (1 - operands[0] / operands[1]) >= threshold (per-seed cells)
  kNotMeasured,  // nothing of ours measures it (peer systems not run, real-only data)
};

struct Claim {
  std::string id;         // "001-C3"
  std::string paper;      // "000" .. "004"
  std::string source;     // the paper's section / table, e.g. "Sec. 4.2, Table 1"
  std::string statement;  // the paper's claim, quoted or paraphrased
  ClaimKind kind = ClaimKind::kLess;
  std::vector<ClaimOperand> operands;
  // kAtLeast / kAtMost / kImprovement: the threshold, a literal (threshold_text says where it comes
  // from) or, when threshold_paper names a cell, the paper's value (an improvement when
  // threshold_paper_base names a second cell: 100 (1 - paper / base)).
  double threshold = 0.0;
  std::string threshold_text;
  PaperRef threshold_paper;
  PaperRef threshold_paper_base;
  double low = 0.0, high = 0.0;  // kWithin
  // A measured explanation for a "not reproduced" verdict, citing where it was measured; "" = open.
  std::string explanation;
};

std::vector<Claim> Claims000();
std::vector<Claim> Claims001();
std::vector<Claim> Claims002();
std::vector<Claim> Claims003();
std::vector<Claim> Claims004();
// Every paper's claims in id order.
std::vector<Claim> AllClaims();

// ---- verdicts ----
enum class Verdict { kReproduced, kReproducedWithinSd, kNotReproducedWithinSd, kNotReproduced, kNotMeasured };
std::string VerdictText(Verdict v);

// A number of ours: mean and S.D. over seeds (sd = 0 when the report gives none).
struct Measured {
  double mean = 0.0;
  double sd = 0.0;
  bool has_sd = false;
};

// a < b (strict) or a <= b: holds on the means; "within S.D." when [mean ± S.D.] intervals overlap.
Verdict CompareLower(const Measured& a, const Measured& b, bool strict);
// a below every one of others: the worst of the pairwise verdicts.
Verdict LowestOf(const Measured& a, const std::vector<Measured>& others);
// a >= t (at_least) or a <= t: "within S.D." when t lies inside [mean - S.D., mean + S.D.].
Verdict CompareThreshold(const Measured& a, double t, bool at_least);
// low <= a <= high: "within S.D." when the interval and the range overlap but one is not inside.
Verdict InRange(const Measured& a, double low, double high);
// Mean and population S.D. of 100 (1 - a_i / b_i) over paired seeds (sizes must match, b_i != 0).
Measured PerSeedImprovement(const std::vector<double>& a, const std::vector<double>& b);
// The worse of two verdicts (reproduced < within S.D. < not reproduced within S.D. < not reproduced).
Verdict Worse(Verdict a, Verdict b);

}  // namespace dynref::reproduce
