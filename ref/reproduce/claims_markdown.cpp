// The Markdown of reports/CLAIMS.md (claims_ledger.h): header with the verdict definitions and the
// counts, the reports read, then one table per paper.
#include <map>
#include <set>
#include <sstream>

#include "core/format.h"
#include "core/version.h"
#include "reproduce/claims_ledger.h"

namespace dynref::reproduce {
namespace {

const std::vector<Verdict>& LedgerVerdicts() {
  static const std::vector<Verdict> v = {Verdict::kReproduced, Verdict::kReproducedWithinSd,
                                         Verdict::kNotReproducedWithinSd, Verdict::kNotReproduced,
                                         Verdict::kNotMeasured};
  return v;
}

std::string PaperTitle(const std::string& paper) {
  static const std::map<std::string, std::string> titles = {{"000", "000 MGD-SLAM"},
                                                            {"001", "001 SGDO-SLAM"},
                                                            {"002", "002 semantic mapping"},
                                                            {"003", "003 motion-blur SLAM"},
                                                            {"004", "004 enhanced-epipolar SLAM"}};
  const auto it = titles.find(paper);
  return it == titles.end() ? paper : it->second;
}

// A table cell: '|' escaped, newlines flattened.
std::string LedgerCell(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|')
      out += "\\|";
    else
      out += c == '\n' ? ' ' : c;
  }
  return out;
}

std::string KindRelation(const ClaimResult& r) {
  const Claim& c = r.claim;
  const std::string t = FormatFixed(r.threshold, 2);
  switch (c.kind) {
    case ClaimKind::kLess: return "checked: " + c.operands[0].label + " < " + c.operands[1].label;
    case ClaimKind::kGreater: return "checked: " + c.operands[0].label + " > " + c.operands[1].label;
    case ClaimKind::kNoWorse: return "checked: " + c.operands[0].label + " <= " + c.operands[1].label;
    case ClaimKind::kLowestOf: return "checked: " + c.operands[0].label + " lowest";
    case ClaimKind::kAtLeast: return "checked: >= " + t;
    case ClaimKind::kAtMost: return "checked: <= " + t;
    case ClaimKind::kWithin: return "checked: in " + FormatFixed(c.low, 1) + "-" + FormatFixed(c.high, 1);
    case ClaimKind::kImprovement: return "checked: per-seed improvement >= " + t + " %";
    case ClaimKind::kNotMeasured: break;
  }
  return "";
}

std::string OursText(const ClaimResult& r) {
  if (r.claim.kind == ClaimKind::kNotMeasured) return "-";
  std::string s;
  for (const ResolvedOperand& o : r.operands) s += (s.empty() ? "" : "; ") + o.label + " " + o.ours.text;
  if (r.claim.kind == ClaimKind::kImprovement && r.verdict != Verdict::kNotMeasured)
    s += "; improvement " + FormatFixed(r.derived.mean, 1) + " ± " + FormatFixed(r.derived.sd, 1) + " %";
  return s + " (" + r.runs + "; " + KindRelation(r) + ")";
}

std::string PaperText(const ClaimResult& r) {
  std::string s;
  for (const ResolvedOperand& o : r.operands)
    if (o.has_paper) s += (s.empty() ? "" : "; ") + o.label + " " + o.paper_text;
  const Claim& c = r.claim;
  if (!c.threshold_paper.csv.empty())
    s += (s.empty() ? "" : "; ") + std::string("threshold ") + FormatFixed(r.threshold, 2) + " (reports/paper-tables/" +
         c.threshold_paper.csv + ")";
  else if (!c.threshold_text.empty())
    s += (s.empty() ? "" : "; ") + c.threshold_text;
  return s.empty() ? "-" : s;
}

std::string ExplanationText(const ClaimResult& r) {
  if (r.verdict == Verdict::kNotReproduced || r.verdict == Verdict::kNotReproducedWithinSd)
    return r.claim.explanation.empty() ? "open" : r.claim.explanation;
  if (r.verdict == Verdict::kNotMeasured) return r.claim.explanation.empty() ? "-" : r.claim.explanation;
  return "-";
}

std::string LinksText(const ClaimResult& r, const std::string& prefix) {
  std::set<std::pair<std::string, int>> seen;
  std::string s;
  for (const ResolvedOperand& o : r.operands) {
    if (!seen.insert({o.report, o.ours.line}).second) continue;
    const std::string line = std::to_string(o.ours.line);
    s += (s.empty() ? "" : ", ") + std::string("[") + o.report + ":" + line + "](" + prefix + o.report +
         "?plain=1#L" + line + ")";
  }
  return s.empty() ? "-" : s;
}

void WriteCounts(std::ostringstream& md, const std::vector<ClaimResult>& results) {
  std::map<std::string, std::map<Verdict, int>> by_paper;
  std::map<Verdict, int> total;
  for (const ClaimResult& r : results) {
    ++by_paper[r.claim.paper][r.verdict];
    ++total[r.verdict];
  }
  md << "## Counts\n\n| paper | claims |";
  for (Verdict v : LedgerVerdicts()) md << " " << VerdictText(v) << " |";
  md << "\n|---|---|";
  for (size_t i = 0; i < LedgerVerdicts().size(); ++i) md << "---|";
  md << "\n";
  auto row = [&](const std::string& name, std::map<Verdict, int>& counts) {
    int n = 0;
    for (const auto& [v, k] : counts) n += k;
    md << "| " << name << " | " << n << " |";
    for (Verdict v : LedgerVerdicts()) md << " " << counts[v] << " |";
    md << "\n";
  };
  for (auto& [paper, counts] : by_paper) row(PaperTitle(paper), counts);
  row("all", total);
}

void WriteReportsRead(std::ostringstream& md, const std::vector<ClaimResult>& results, const std::string& prefix) {
  std::map<std::string, const ResolvedOperand*> reports;
  for (const ClaimResult& r : results)
    for (const ResolvedOperand& o : r.operands) reports.emplace(o.report, &o);
  md << "\n## Reports read\n\n| report | written by commit | runs |\n|---|---|---|\n";
  for (const auto& [name, o] : reports)
    md << "| [" << name << "](" << prefix << name << ") | " << o->report_commit << " | " << o->report_runs << " |\n";
}

}  // namespace

std::string ClaimsLedgerMarkdown(const std::vector<ClaimResult>& results, const std::string& link_prefix) {
  std::ostringstream md;
  md << "# Claims ledger: the five papers' relative claims against dynref's reports\n\n"
     << "Written by `dynref reproduce claims` (dynref " << DYNREF_VERSION << ", commit " << DYNREF_GIT_COMMIT
     << ") from the committed reports (`reports/<table>.md`) and the papers' tables (`reports/paper-tables/`). "
     << "Do not edit by hand. The registry of claims: `ref/reproduce/claims_000.cpp` .. `claims_004.cpp`.\n\n"
     << "Our numbers are the reports' cells: mean ± population S.D. over the synthesis seeds (the runs of each "
     << "report: its seeds and frames are named per claim). Verdicts:\n\n"
     << "- **reproduced**: the claimed relation holds on the means and the intervals [mean - S.D., mean + S.D.] do "
     << "not overlap (a threshold lies outside our interval, on the claimed side; a range contains it).\n"
     << "- **reproduced (within S.D.)**: the relation holds on the means, but the intervals overlap (the threshold "
     << "lies inside our interval; the interval sticks out of the range).\n"
     << "- **not reproduced (within S.D.)**: the relation fails on the means, but the intervals overlap.\n"
     << "- **not reproduced**: the relation fails on the means and the intervals do not overlap.\n"
     << "- **not measured**: dynref has no number for it (peer systems not run, real-only data, a variant that "
     << "never initialised); the reason is given.\n\n"
     << "A cell without an S.D. (per-module ms, summed precision/recall, keypoint counts) counts with S.D. 0. "
     << "\"lowest\" takes the worst of the pairwise verdicts. An improvement is 100 (1 - ours / baseline) per seed "
     << "from the report's per-seed cells, then mean ± S.D. The comparisons are on synthetic analogues of the "
     << "papers' sequences, never against the papers' absolute numbers (shown for reference). Every \"not "
     << "reproduced\" carries a measured explanation and where it was measured, or \"open\".\n\n";
  WriteCounts(md, results);
  WriteReportsRead(md, results, link_prefix);
  std::string paper;
  for (const ClaimResult& r : results) {
    if (r.claim.paper != paper) {
      paper = r.claim.paper;
      md << "\n## " << PaperTitle(paper) << "\n\n"
         << "| id | paper's claim (source) | ours | paper | verdict | explanation | report |\n"
         << "|---|---|---|---|---|---|---|\n";
    }
    md << "| " << r.claim.id << " | " << LedgerCell(r.claim.statement + " (" + r.claim.source + ")") << " | "
       << LedgerCell(OursText(r)) << " | " << LedgerCell(PaperText(r)) << " | " << VerdictText(r.verdict) << " | "
       << LedgerCell(ExplanationText(r)) << " | " << LedgerCell(LinksText(r, link_prefix)) << " |\n";
  }
  return md.str();
}

}  // namespace dynref::reproduce
