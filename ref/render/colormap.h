// Perceptual colour map for probabilities: viridis (van der Walt & Smith, matplotlib), as the
// degree-6 polynomial fit by Matt Zucker (public domain); max error < 1/255 per channel.
#pragma once
#include <algorithm>
#include <cmath>

#include "render/canvas.h"

namespace dynref::render {

inline Rgb Viridis(double t) {
  t = std::clamp(std::isnan(t) ? 0.0 : t, 0.0, 1.0);
  static const double c[7][3] = {{0.2777273272234177, 0.005407344544966578, 0.3340998053353061},
                                 {0.1050930431085774, 1.404613529898575, 1.384590162594685},
                                 {-0.3308618287255563, 0.214847559468213, 0.09509516302823659},
                                 {-4.634230498983486, -5.799100973351585, -19.33244095627987},
                                 {6.228269936347081, 14.17993336680509, 56.69055260068105},
                                 {4.776384997670288, -13.74514537774601, -65.35303263337234},
                                 {-5.435455855934631, 4.645852612178535, 26.3124352495832}};
  double v[3];
  for (int ch = 0; ch < 3; ++ch) {
    double acc = c[6][ch];
    for (int k = 5; k >= 0; --k) acc = acc * t + c[k][ch];
    v[ch] = std::clamp(acc, 0.0, 1.0);
  }
  auto q = [](double x) { return static_cast<uint8_t>(std::lround(x * 255.0)); };
  return Rgb{q(v[0]), q(v[1]), q(v[2])};
}

}  // namespace dynref::render
