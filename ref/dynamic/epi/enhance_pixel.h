// Eq. (2) at one pixel (enhance.h c), shared by LocalWeightedEnhance and the BOA's EnhanceTerms so
// both keep the reconstruction's exact double operation order.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace dynref::epi::pixel {

// |I_s - mu_w| / (sigma_w + e0), with d = I_s - mu_w.
inline double ContrastRatio(float i, float m, float m2, double e0, double* d) {
  const double sigma = std::sqrt(std::max(0.0, double(m2) - double(m) * m));
  *d = double(i) - m;
  return std::abs(*d) / (sigma + e0);
}

// Where the clamp of m + (1 + W) d lands whatever W in [0, inf] is: (1 + W) d moves away from d as
// W grows and double rounding is monotonic, so once m + d is out of [0, 1] the result is that
// bound. W = alpha * ratio^p is in [0, inf] (never NaN) when alpha > 0, so callers ask only then.
enum Side : uint8_t { kInside = 0, kHigh = 1, kLow = 2 };
inline Side Saturation(float m, double d) {
  const double plain = m + d;
  if (d > 0 && plain >= 1.0) return kHigh;
  if (d < 0 && plain <= 0.0) return kLow;
  return kInside;
}
inline float BoundOf(Side s) { return s == kHigh ? 1.0f : 0.0f; }

// E = clip01(mu_w + (1 + W) d).
inline float Weighted(float m, double d, double w) { return float(std::clamp(m + (1.0 + w) * d, 0.0, 1.0)); }

}  // namespace dynref::epi::pixel
