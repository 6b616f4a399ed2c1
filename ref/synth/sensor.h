// Shading of the G-buffer (Lambert with ceiling point lights + ambient + emission) and the
// RGB-D sensor model: Kinect-like depth noise/quantisation/range/edge dropouts, RGB vignetting,
// gamma, signal-dependent noise, optional low-light exposure.
#pragma once
#include <opencv2/core.hpp>

#include "core/rng.h"
#include "synth/raster.h"
#include "synth/scene.h"

namespace dynref::synth {

struct SensorModel {
  double depth_factor = 5000.0;  // PNG units per metre (TUM)
  double max_depth_m = 4.5;      // no depth beyond (Kinect range)
  double min_depth_m = 0.4;
  // Axial noise sigma(z) = a + b (z - c)^2 (Nguyen et al. 2012 Kinect model, as in issue 3).
  double sigma_a = 0.0012, sigma_b = 0.0019, sigma_c = 0.4;
  // A pixel is on a depth edge if a 4-neighbour is closer by more than max(abs, rel * z).
  double edge_abs_m = 0.05, edge_rel = 0.03;
  double edge_drop_p1 = 0.5;     // probability to drop the far-side edge pixel
  double edge_drop_p2 = 0.25;    // ... and the next pixel beyond it (shadow band of 2 px)
  // RGB
  double exposure = 0.8;         // radiance scale before the tone curve
  double vignetting = 0.25;      // radiance * (1 - v r^2), r = normalised radius
  double read_noise = 1.5;       // 8-bit units
  double shot_noise = 0.02;      // variance per 8-bit unit of signal
  double low_light_exposure = 0.08, low_light_read_noise = 2.5, low_light_black = 4.0;
  double SigmaZ(double z) const { return sigma_a + sigma_b * (z - sigma_c) * (z - sigma_c); }
};

// Linear radiance (CV_32FC3, BGR order) of the G-buffer seen from T_wc.
void ShadeRadiance(const Scene& scene, const Intrinsics& K, const SE3& T_wc, const GBuffer& gb, cv::Mat* radiance);
// 8-bit BGR image from (possibly exposure-averaged) radiance.
cv::Mat SenseRgb(const SensorModel& s, const cv::Mat& radiance, bool low_light, Rng& rng);
// 16-bit depth (depth_factor units, 0 = no measurement) from the true depth of the G-buffer.
cv::Mat SenseDepth(const SensorModel& s, const GBuffer& gb, Rng& rng);
// Standard normal through a fixed inverse-CDF table (fast; 12-bit resolution, |x| <= 3.4).
double TableGaussian(uint32_t bits12);

}  // namespace dynref::synth
