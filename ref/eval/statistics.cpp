#include "eval/statistics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynref {

ErrorStats ComputeErrorStats(const std::vector<double>& errors) {
  if (errors.empty()) throw std::logic_error("ComputeErrorStats: no errors");
  ErrorStats s;
  const double n = static_cast<double>(errors.size());
  s.count = errors.size();
  double sum = 0, sse = 0;
  for (double e : errors) {
    sum += e;
    sse += e * e;
  }
  s.sse = sse;
  s.rmse = std::sqrt(sse / n);
  s.mean = sum / n;
  double var = 0;
  for (double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const size_t m = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  s.min = sorted.front();
  s.max = sorted.back();
  return s;
}

}  // namespace dynref
