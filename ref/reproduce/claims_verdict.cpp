// Verdicts of the claims ledger from our means and S.D.s over seeds (definitions: CLAIMS.md header,
// written by claims_ledger.cpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "reproduce/claims.h"

namespace dynref::reproduce {
namespace {

Verdict FromHoldsAndOverlap(bool holds, bool overlap) {
  if (holds) return overlap ? Verdict::kReproducedWithinSd : Verdict::kReproduced;
  return overlap ? Verdict::kNotReproducedWithinSd : Verdict::kNotReproduced;
}

}  // namespace

std::string VerdictText(Verdict v) {
  switch (v) {
    case Verdict::kReproduced: return "reproduced";
    case Verdict::kReproducedWithinSd: return "reproduced (within S.D.)";
    case Verdict::kNotReproducedWithinSd: return "not reproduced (within S.D.)";
    case Verdict::kNotReproduced: return "not reproduced";
    case Verdict::kNotMeasured: return "not measured";
  }
  return "?";
}

Verdict Worse(Verdict a, Verdict b) { return static_cast<int>(a) >= static_cast<int>(b) ? a : b; }

Verdict CompareLower(const Measured& a, const Measured& b, bool strict) {
  const bool holds = strict ? a.mean < b.mean : a.mean <= b.mean;
  const double spread = a.sd + b.sd;
  const bool overlap = spread > 0 && std::fabs(a.mean - b.mean) <= spread;
  return FromHoldsAndOverlap(holds, overlap);
}

Verdict LowestOf(const Measured& a, const std::vector<Measured>& others) {
  Verdict v = Verdict::kReproduced;
  for (const Measured& o : others) v = Worse(v, CompareLower(a, o, true));
  return v;
}

Verdict CompareThreshold(const Measured& a, double t, bool at_least) {
  const bool holds = at_least ? a.mean >= t : a.mean <= t;
  const bool inside = a.sd > 0 && std::fabs(a.mean - t) <= a.sd;
  return FromHoldsAndOverlap(holds, inside);
}

Verdict InRange(const Measured& a, double low, double high) {
  const bool holds = a.mean >= low && a.mean <= high;
  const bool inside = a.mean - a.sd >= low && a.mean + a.sd <= high;
  const bool overlap = a.mean + a.sd >= low && a.mean - a.sd <= high;
  if (holds) return inside ? Verdict::kReproduced : Verdict::kReproducedWithinSd;
  return overlap && a.sd > 0 ? Verdict::kNotReproducedWithinSd : Verdict::kNotReproduced;
}

Measured PerSeedImprovement(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.empty()) throw std::invalid_argument("per-seed improvement: seed counts differ");
  std::vector<double> cut;
  for (size_t i = 0; i < a.size(); ++i) {
    if (b[i] == 0) throw std::invalid_argument("per-seed improvement: a zero baseline");
    cut.push_back(100.0 * (1.0 - a[i] / b[i]));
  }
  double sum = 0, sq = 0;
  for (double c : cut) sum += c;
  Measured m;
  m.mean = sum / static_cast<double>(cut.size());
  for (double c : cut) sq += (c - m.mean) * (c - m.mean);
  m.sd = std::sqrt(sq / static_cast<double>(cut.size()));
  m.has_sd = cut.size() > 1;
  return m;
}

}  // namespace dynref::reproduce
