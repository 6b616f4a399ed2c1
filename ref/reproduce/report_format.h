// Number formatting of the Markdown reports (deterministic, no locale).
#pragma once
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <string>
#include <vector>

#include "core/format.h"
#include "eval/statistics.h"

namespace dynref::reproduce {

// Fixed decimals, "-" for NaN/inf.
inline std::string Num(double v, int decimals = 4) { return std::isfinite(v) ? FormatFixed(v, decimals) : "-"; }
// Shortest %g form: 0.1 -> "0.1", 100 -> "100" (names and headers only, never results).
inline std::string Short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}
// Seeds as given to --seeds: "1,2,3".
inline std::string SeedListText(const std::vector<uint64_t>& seeds) {
  std::string s;
  for (uint64_t x : seeds) s += (s.empty() ? "" : ",") + std::to_string(x);
  return s;
}
// Mean over seeds; NaN for none.
inline double Mean(const std::vector<double>& v) { return v.empty() ? std::nan("") : ComputeErrorStats(v).mean; }
// Mean and population S.D. over seeds ("n/a" for none, no S.D. for one).
inline std::string MeanSd(const std::vector<double>& v, int decimals = 4) {
  if (v.empty()) return "n/a";
  const ErrorStats st = ComputeErrorStats(v);
  return Num(st.mean, decimals) + (v.size() > 1 ? " ± " + Num(st.std, decimals) : "");
}
// A section listing the CSV's notes on the paper's table (inconsistencies found when extracting it; "" when none).
inline std::string PaperNotes(const std::string& file, const std::vector<std::string>& notes) {
  if (notes.empty()) return "";
  std::string s = "\n## Notes on the paper's table (`reports/paper-tables/" + file + "`)\n\n";
  for (const std::string& n : notes) s += "- " + n + "\n";
  return s;
}
// 100 num / den with one decimal, "-" when den = 0.
inline std::string Pct(double num, double den) { return den > 0 ? FormatFixed(100.0 * num / den, 1) : "-"; }

}  // namespace dynref::reproduce
