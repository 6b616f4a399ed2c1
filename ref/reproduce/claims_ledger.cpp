// Resolution of the claims registry against the reports and paper tables, and the verdicts.
#include "reproduce/claims_ledger.h"

#include <cmath>
#include <filesystem>
#include <map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "reproduce/paper_table.h"

namespace dynref::reproduce {
namespace {

// Reports and paper tables read once per resolution.
class ClaimSources {
 public:
  explicit ClaimSources(std::string dir) : dir_(std::move(dir)) {}

  ReportValue Ours(const ReportRef& ref) {
    const std::string path = ReportPath(ref.report);
    const ReportTable t = FindReportTable(path, Lines(path), ref.heading);
    return ReadReportValue(t, ref.row, ref.column);
  }
  std::string Runs(const std::string& report) {
    const ReportProvenance p = Provenance(report);
    std::string s = p.seeds.empty() ? "seeds as in the report" : "seeds " + p.seeds;
    if (p.frames == "0")
      s += ", the papers' lengths (--frames 0)";  // each preset as long as the real sequence it imitates
    else if (!p.frames.empty())
      s += ", " + p.frames + " frames";
    return s;
  }
  ReportProvenance Provenance(const std::string& report) {
    const std::string path = ReportPath(report);
    return ReadReportProvenance(path, Lines(path));
  }
  double Paper(const PaperRef& ref) {
    const std::string path = dir_ + "/paper-tables/" + ref.csv;
    const double v = Table(path).Cell(ref.row, ref.column);
    if (!std::isfinite(v))
      throw InputError(path, "no number at row '" + ref.row + "', column '" + ref.column + "'");
    return v;
  }
  // The cell as printed (Paper() has checked it exists).
  std::string PaperText(const PaperRef& ref) {
    const PaperTable& t = Table(dir_ + "/paper-tables/" + ref.csv);
    for (size_t c = 0; c < t.header.size(); ++c)
      if (t.header[c] == ref.column) return t.rows.at(ref.row).at(c);
    return "";
  }

 private:
  std::string ReportPath(const std::string& report) const { return dir_ + "/" + report; }
  const PaperTable& Table(const std::string& path) {
    auto it = papers_.find(path);
    if (it == papers_.end()) it = papers_.emplace(path, ReadPaperTable(path)).first;
    return it->second;
  }
  const std::vector<std::string>& Lines(const std::string& path) {
    auto it = lines_.find(path);
    if (it == lines_.end()) it = lines_.emplace(path, ReadReportLines(path)).first;
    return it->second;
  }
  std::string dir_;
  std::map<std::string, std::vector<std::string>> lines_;
  std::map<std::string, PaperTable> papers_;
};

Measured AsMeasured(const ReportValue& v) { return {v.mean, v.has_sd ? v.sd : 0.0, v.has_sd}; }

double ResolveThreshold(const Claim& c, ClaimSources& src) {
  if (c.threshold_paper.csv.empty()) return c.threshold;
  const double v = src.Paper(c.threshold_paper);
  if (c.threshold_paper_base.csv.empty()) return v;
  return 100.0 * (1.0 - v / src.Paper(c.threshold_paper_base));
}

Measured ImprovementOf(const ClaimResult& r) {
  for (const ResolvedOperand& o : r.operands)
    if (o.ours.seeds.empty())
      throw InputError(o.ours.file, o.ours.line,
                       r.claim.id + ": an improvement needs per-seed values, the cell is '" + o.ours.text + "'");
  return PerSeedImprovement(r.operands[0].ours.seeds, r.operands[1].ours.seeds);
}

size_t NeededOperands(ClaimKind k) {
  switch (k) {
    case ClaimKind::kNotMeasured: return 0;
    case ClaimKind::kAtLeast:
    case ClaimKind::kAtMost:
    case ClaimKind::kWithin: return 1;
    default: return 2;
  }
}

}  // namespace

Verdict ClaimVerdict(const ClaimResult& r) {
  const ClaimKind k = r.claim.kind;
  if (k == ClaimKind::kNotMeasured) return Verdict::kNotMeasured;
  for (const ResolvedOperand& o : r.operands)
    if (!o.ours.numeric) return Verdict::kNotMeasured;
  const Measured a = AsMeasured(r.operands[0].ours);
  switch (k) {
    case ClaimKind::kLess: return CompareLower(a, AsMeasured(r.operands[1].ours), true);
    case ClaimKind::kNoWorse: return CompareLower(a, AsMeasured(r.operands[1].ours), false);
    case ClaimKind::kGreater: return CompareLower(AsMeasured(r.operands[1].ours), a, true);
    case ClaimKind::kLowestOf: {
      std::vector<Measured> others;
      for (size_t i = 1; i < r.operands.size(); ++i) others.push_back(AsMeasured(r.operands[i].ours));
      return LowestOf(a, others);
    }
    case ClaimKind::kAtLeast: return CompareThreshold(a, r.threshold, true);
    case ClaimKind::kAtMost: return CompareThreshold(a, r.threshold, false);
    case ClaimKind::kWithin: return InRange(a, r.claim.low, r.claim.high);
    case ClaimKind::kImprovement: return CompareThreshold(r.derived, r.threshold, true);
    case ClaimKind::kNotMeasured: break;
  }
  return Verdict::kNotMeasured;
}

std::vector<ClaimResult> ResolveClaims(const std::vector<Claim>& claims, const std::string& reports_dir) {
  ClaimSources src(reports_dir);
  std::vector<ClaimResult> out;
  for (const Claim& c : claims) {
    if (c.operands.size() < NeededOperands(c.kind))
      throw std::logic_error(c.id + ": too few operands for its kind");
    ClaimResult r;
    r.claim = c;
    for (const ClaimOperand& op : c.operands) {
      ResolvedOperand o{op.label, src.Ours(op.ours), op.ours.report, src.Provenance(op.ours.report).commit,
                        src.Runs(op.ours.report), 0.0, "", false};
      if (!op.paper.csv.empty()) {
        o.paper = src.Paper(op.paper);
        o.paper_text = src.PaperText(op.paper);
        o.has_paper = true;
      }
      r.operands.push_back(o);
    }
    if (!c.operands.empty()) r.runs = src.Runs(c.operands[0].ours.report);
    r.threshold = ResolveThreshold(c, src);
    const bool all_numeric = [&] {
      for (const ResolvedOperand& o : r.operands)
        if (!o.ours.numeric) return false;
      return true;
    }();
    if (c.kind == ClaimKind::kImprovement && all_numeric) r.derived = ImprovementOf(r);
    r.verdict = ClaimVerdict(r);
    out.push_back(std::move(r));
  }
  return out;
}

int RunClaimsLedger(const ClaimsArgs& args) {
  namespace fs = std::filesystem;
  const std::vector<ClaimResult> results = ResolveClaims(AllClaims(), args.reports);
  const fs::path out_dir = fs::absolute(fs::path(args.out)).parent_path().lexically_normal();
  fs::path rep_dir = fs::absolute(fs::path(args.reports)).lexically_normal();
  if (!rep_dir.has_filename()) rep_dir = rep_dir.parent_path();  // "reports/" -> "reports"
  std::string prefix = rep_dir.lexically_relative(out_dir).generic_string();
  if (prefix == "." || prefix.empty())
    prefix.clear();
  else if (prefix.back() != '/')
    prefix += "/";
  AtomicWriteFile(args.out, ClaimsLedgerMarkdown(results, prefix));
  return kExitOk;
}

std::vector<Claim> AllClaims() {
  std::vector<Claim> all;
  for (auto part : {Claims000(), Claims001(), Claims002(), Claims003(), Claims004()})
    all.insert(all.end(), part.begin(), part.end());
  return all;
}

}  // namespace dynref::reproduce
