// seed 004 Module A: the butterfly optimisation algorithm (BOA, Arora & Singh 2019) that tunes the
// enhancement weights (alpha, p), as the paper describes it: a global search with Cauchy mutation
// and a local search with differential steps. Deterministic: every draw comes from the caller's
// dynref Rng, the budget is fixed (population x iterations fitness evaluations), no early stop.
//   fragrance f_i = c * F_i^a  (F_i = fitness shifted to be > 0 within the population)
//   global (probability switch_p): x' = x_i + (r^2 g* - x_i) f_i + scale * Cauchy(0,1) * (ub - lb)
//   local: x' = x_i + r * (x_j - x_k) * f_i / max f  (j, k distinct random members)
//   greedy: x_i <- x' when fit(x') > fit(x_i); g* = best so far (ties keep the earlier).
#pragma once
#include <functional>
#include <vector>

#include "core/rng.h"

namespace dynref::epi {

struct BoaOptions {
  int population = 20;       // not stated (spec 004 (c): 20 / 30)
  int iterations = 30;
  double switch_p = 0.8;     // BOA paper default
  double sensory_c = 0.01;   // BOA paper default
  double power_a = 0.1;      // BOA paper default
  double cauchy_scale = 0.05;  // not stated: Cauchy step in units of the search range
  void Check() const;        // std::invalid_argument naming the field
};

struct BoaResult {
  std::vector<double> best;
  double best_fitness = 0;
  std::vector<double> best_per_iteration;  // after each iteration
  int evaluations = 0;
};

using Fitness = std::function<double(const std::vector<double>&)>;

// Maximises `fitness` over the box [lower, upper] (same size, lower < upper).
BoaResult ButterflyOptimise(const Fitness& fitness, const std::vector<double>& lower,
                            const std::vector<double>& upper, const BoaOptions& o, Rng& rng);

}  // namespace dynref::epi
