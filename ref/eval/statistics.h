// Error statistics as printed by TUM's evaluate_ate.py / evaluate_rpe.py and evo.
#pragma once
#include <cstddef>
#include <vector>

namespace dynref {

struct ErrorStats {
  size_t count = 0;
  double rmse = 0;    // sqrt(sse / n)
  double mean = 0;
  double median = 0;  // numpy.median: mean of the two middle values for even n
  double std = 0;     // population standard deviation (numpy.std, ddof = 0)
  double min = 0;
  double max = 0;
  double sse = 0;     // sum of squared errors (evo's "sse")
};

// Requires a non-empty list (callers report "zero pairs" themselves).
ErrorStats ComputeErrorStats(const std::vector<double>& errors);

}  // namespace dynref
