#include "dynamic/epi/butterfly.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dynref::epi {

void BoaOptions::Check() const {
  if (population < 3) throw std::invalid_argument("population must be >= 3");
  if (iterations < 1) throw std::invalid_argument("iterations must be >= 1");
  if (!(switch_p >= 0 && switch_p <= 1)) throw std::invalid_argument("switch_p must be in [0, 1]");
  if (!(sensory_c > 0)) throw std::invalid_argument("sensory_c must be > 0");
  if (!(power_a >= 0 && power_a <= 1)) throw std::invalid_argument("power_a must be in [0, 1]");
  if (!(cauchy_scale >= 0)) throw std::invalid_argument("cauchy_scale must be >= 0");
}

BoaResult ButterflyOptimise(const Fitness& fitness, const std::vector<double>& lo, const std::vector<double>& hi,
                            const BoaOptions& o, Rng& rng) {
  o.Check();
  const size_t d = lo.size();
  if (d == 0 || hi.size() != d) throw std::invalid_argument("ButterflyOptimise: bounds of different sizes");
  for (size_t k = 0; k < d; ++k)
    if (!(lo[k] < hi[k])) throw std::invalid_argument("ButterflyOptimise: lower bound not below upper");
  BoaResult r;
  auto clip = [&](std::vector<double>& x) {
    for (size_t k = 0; k < d; ++k) x[k] = std::clamp(x[k], lo[k], hi[k]);
  };
  auto eval = [&](const std::vector<double>& x) {
    ++r.evaluations;
    const double f = fitness(x);
    return std::isnan(f) ? -std::numeric_limits<double>::infinity() : f;
  };
  const size_t n = size_t(o.population);
  std::vector<std::vector<double>> x(n, std::vector<double>(d));
  std::vector<double> fit(n);
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < d; ++k) x[i][k] = rng.Uniform(lo[k], hi[k]);
    fit[i] = eval(x[i]);
  }
  size_t best = 0;
  for (size_t i = 1; i < n; ++i)
    if (fit[i] > fit[best]) best = i;
  r.best = x[best];
  r.best_fitness = fit[best];
  for (int it = 0; it < o.iterations; ++it) {
    // Fragrance from fitness shifted to be positive within the population.
    double fmin = std::numeric_limits<double>::infinity(), fmax = -fmin;
    for (double f : fit)
      if (std::isfinite(f)) fmin = std::min(fmin, f), fmax = std::max(fmax, f);
    std::vector<double> frag(n, 0.0);
    double frag_max = 0;
    for (size_t i = 0; i < n; ++i) {
      const double stim = std::isfinite(fit[i]) && std::isfinite(fmin) ? fit[i] - fmin + 1e-12 : 1e-12;
      frag[i] = o.sensory_c * std::pow(stim, o.power_a);
      frag_max = std::max(frag_max, frag[i]);
    }
    for (size_t i = 0; i < n; ++i) {
      std::vector<double> y = x[i];
      const double rr = rng.Uniform01();
      if (rng.Bernoulli(o.switch_p)) {  // global: towards g*, plus a Cauchy jump
        for (size_t k = 0; k < d; ++k) {
          const double cauchy = std::tan(M_PI * (rng.Uniform01() - 0.5));
          y[k] += (rr * rr * r.best[k] - x[i][k]) * frag[i] + o.cauchy_scale * cauchy * (hi[k] - lo[k]);
        }
      } else {  // local: differential step between two other members
        size_t j = size_t(rng.UniformInt(0, int64_t(n) - 1)), k2 = size_t(rng.UniformInt(0, int64_t(n) - 1));
        while (j == i) j = size_t(rng.UniformInt(0, int64_t(n) - 1));
        while (k2 == i || k2 == j) k2 = size_t(rng.UniformInt(0, int64_t(n) - 1));
        const double scale = frag_max > 0 ? frag[i] / frag_max : 1.0;
        for (size_t k = 0; k < d; ++k) y[k] += rr * (x[j][k] - x[k2][k]) * scale;
      }
      clip(y);
      const double fy = eval(y);
      if (fy > fit[i]) {
        x[i] = y;
        fit[i] = fy;
        if (fy > r.best_fitness) r.best = y, r.best_fitness = fy;
      }
    }
    r.best_per_iteration.push_back(r.best_fitness);
  }
  return r;
}

}  // namespace dynref::epi
