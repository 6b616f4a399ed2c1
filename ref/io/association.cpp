#include "io/association.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>

#include "core/error.h"
#include "core/format.h"

namespace dynref {

const char* AssociationKindName(AssociationKind kind) {
  return kind == AssociationKind::kTum ? "tum" : "evo";
}

std::vector<StampMatch> AssociateTum(const std::vector<double>& first,
                                     const std::vector<double>& second, double max_difference_s,
                                     double offset_s) {
  struct Candidate {
    double diff;
    uint32_t ia, ib;
  };
  std::vector<double> shifted(second.size());
  for (size_t j = 0; j < second.size(); ++j) shifted[j] = second[j] + offset_s;
  // Candidates lie in a window around each a (second is ascending); the window is widened by one
  // element on each side so the tool's exact strict test below decides alone.
  auto window = [&](double a) {
    size_t lo = std::lower_bound(shifted.begin(), shifted.end(), a - max_difference_s) -
                shifted.begin();
    size_t hi = std::upper_bound(shifted.begin(), shifted.end(), a + max_difference_s) -
                shifted.begin();
    return std::make_pair(lo > 0 ? lo - 1 : 0, std::min(hi + 1, second.size()));
  };
  // The tool's O(candidates) list can explode for a huge max_difference; refuse instead of
  // exhausting memory.
  constexpr size_t kMaxCandidates = 20000000;
  size_t total = 0;
  for (double a : first) {
    const auto w = window(a);
    total += w.second - w.first;
  }
  if (total > kMaxCandidates || first.size() > UINT32_MAX || second.size() > UINT32_MAX)
    throw InputError("--max-diff", "max difference " + FormatDouble17(max_difference_s) +
                                       " s gives " + std::to_string(total) +
                                       " candidate pairs (limit 20,000,000); use a smaller one");
  std::vector<Candidate> cand;
  cand.reserve(total);
  for (size_t i = 0; i < first.size(); ++i) {
    const double a = first[i];
    const auto w = window(a);
    for (size_t j = w.first; j < w.second; ++j) {
      const double diff = std::abs(a - (second[j] + offset_s));
      if (diff < max_difference_s)
        cand.push_back({diff, static_cast<uint32_t>(i), static_cast<uint32_t>(j)});
    }
  }
  // Python sorts the tuples (diff, a, b): lexicographic, all keys distinct per (a, b).
  // Both lists are strictly increasing, so ordering by index is ordering by stamp.
  std::sort(cand.begin(), cand.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.diff, x.ia, x.ib) < std::tie(y.diff, y.ia, y.ib);
  });
  std::vector<char> used_a(first.size(), 0), used_b(second.size(), 0);
  std::vector<StampMatch> out;
  for (const Candidate& c : cand) {
    if (used_a[c.ia] || used_b[c.ib]) continue;
    used_a[c.ia] = used_b[c.ib] = 1;
    out.push_back({c.ia, c.ib});
  }
  // matches.sort(): by (a, b); a is unique among matches.
  std::sort(out.begin(), out.end(), [](const StampMatch& x, const StampMatch& y) {
    return std::tie(x.first, x.second) < std::tie(y.first, y.second);
  });
  return out;
}

std::vector<StampMatch> AssociateEvo(const std::vector<double>& first,
                                     const std::vector<double>& second, double max_difference_s,
                                     double offset_s) {
  const bool first_longer = first.size() >= second.size();
  const std::vector<double>& shorter = first_longer ? second : first;
  const std::vector<double>& longer = first_longer ? first : second;
  // evo adds offset_2 to the second trajectory: long + offset if first_longer else -offset.
  const double offset = first_longer ? offset_s : -offset_s;
  std::vector<StampMatch> out;
  if (longer.empty()) return out;
  for (size_t s = 0; s < shorter.size(); ++s) {
    // matching_time_indices: diffs = |(stamps_2 + offset) - stamp_1|; index = argmin (first).
    const double stamp = shorter[s];
    size_t best = 0;
    double best_diff = std::abs((longer[0] + offset) - stamp);
    // Binary search for the neighbourhood, then scan it for the exact argmin semantics.
    size_t pos = std::lower_bound(longer.begin(), longer.end(), stamp - offset) - longer.begin();
    size_t lo = pos >= 2 ? pos - 2 : 0;
    size_t hi = std::min(pos + 2, longer.size());
    for (size_t k = lo; k < hi; ++k) {
      const double d = std::abs((longer[k] + offset) - stamp);
      if (d < best_diff || (d == best_diff && k < best)) {
        best_diff = d;
        best = k;
      }
    }
    // argmin over all is monotone-safe: |x - t| is unimodal over an ascending list, so the
    // minimum lies next to the insertion point; index 0 was seeded above for equal values.
    if (best_diff <= max_difference_s) {
      if (first_longer)
        out.push_back({best, s});
      else
        out.push_back({s, best});
    }
  }
  return out;
}

std::vector<StampMatch> Associate(AssociationKind kind, const std::vector<double>& first,
                                  const std::vector<double>& second, double max_difference_s,
                                  double offset_s) {
  return kind == AssociationKind::kTum
             ? AssociateTum(first, second, max_difference_s, offset_s)
             : AssociateEvo(first, second, max_difference_s, offset_s);
}

}  // namespace dynref
