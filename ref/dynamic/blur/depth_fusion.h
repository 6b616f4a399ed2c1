// seed 003 Sec. 3.2, depth fusion: stratified samples of the depth image that fall in a person
// box give the "human value range" O_h = [g_h - alpha, g_h + alpha] around their mean; every box
// pixel whose depth lies in O_h and within 3 sigma of the box's depth statistics joins the mask
// (spec 003 step 3, per-pixel reading of "copy the regions of each grey value in O_h", E5/E6:
// depth in metres, alpha in metres).
#pragma once
#include <opencv2/core.hpp>
#include <vector>

#include "core/rng.h"

namespace dynref::blur {

struct DepthFusionOptions {
  int grid_cols = 16, grid_rows = 12;  // n_reg = cols x rows equal rectangles (not stated)
  int samples_per_cell = 1;            // s_reg (not stated)
  double alpha_m = 0.3;                // half-width of the human value range (not stated)
  double sigma_mult = 3.0;             // paper Sec. 3.2: three standard deviations
  void Check() const;                  // std::invalid_argument naming the field
};

// s_reg uniform pixel positions in each of the n_reg rectangles, row-major cell order, drawn
// from rng (one frame's samples, shared by every box of the frame), each sample's row drawn
// before its column.
std::vector<cv::Point> StratifiedSamples(cv::Size size, const DepthFusionOptions& o, Rng& rng);

struct HumanValueRange {
  int in_box = 0;               // sample positions inside the box (valid depth or not)
  int samples = 0;              // valid-depth samples inside the box (|P_f^i|)
  std::vector<double> sample_depths;  // their depths (m), in sample order (trace)
  double g_h = 0;               // their mean depth (m)
  double lo = 0, hi = 0;        // O_h
  double mu_box = 0, sigma_box = 0;
  int box_valid_px = 0;         // valid-depth pixels in the box
  int fused_px = 0;             // pixels of M_d^i
  bool valid() const { return samples > 0; }
};

// M_d^i for one box into `fused` (CV_8U, set to 255 where the pixel belongs, never cleared).
// A box with no valid sample adds nothing.
HumanValueRange FuseBoxDepth(const cv::Mat& depth_m, const cv::Rect& box, const std::vector<cv::Point>& samples,
                             const DepthFusionOptions& o, cv::Mat* fused);

}  // namespace dynref::blur
