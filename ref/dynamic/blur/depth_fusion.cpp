#include "dynamic/blur/depth_fusion.h"

#include <cmath>
#include <stdexcept>

namespace dynref::blur {

void DepthFusionOptions::Check() const {
  if (grid_cols < 1 || grid_rows < 1) throw std::invalid_argument("grid_cols and grid_rows must be >= 1");
  if (samples_per_cell < 1) throw std::invalid_argument("samples_per_cell must be >= 1");
  if (!(alpha_m > 0)) throw std::invalid_argument("alpha_m must be > 0");
  if (!(sigma_mult > 0)) throw std::invalid_argument("sigma_mult must be > 0");
}

std::vector<cv::Point> StratifiedSamples(cv::Size size, const DepthFusionOptions& o, Rng& rng) {
  std::vector<cv::Point> out;
  out.reserve(size_t(o.grid_cols) * o.grid_rows * o.samples_per_cell);
  for (int r = 0; r < o.grid_rows; ++r) {
    const int y0 = r * size.height / o.grid_rows, y1 = (r + 1) * size.height / o.grid_rows;
    for (int c = 0; c < o.grid_cols; ++c) {
      const int x0 = c * size.width / o.grid_cols, x1 = (c + 1) * size.width / o.grid_cols;
      if (x1 <= x0 || y1 <= y0) continue;  // more cells than pixels
      for (int s = 0; s < o.samples_per_cell; ++s) {
        // Row first, then column: the order GCC gave the two draws when they were the unsequenced
        // arguments of one call (kept so that results do not change; trace verify replays it).
        const int y = int(rng.UniformInt(y0, y1 - 1));
        const int x = int(rng.UniformInt(x0, x1 - 1));
        out.emplace_back(x, y);
      }
    }
  }
  return out;
}

HumanValueRange FuseBoxDepth(const cv::Mat& depth_m, const cv::Rect& box_in, const std::vector<cv::Point>& samples,
                             const DepthFusionOptions& o, cv::Mat* fused) {
  HumanValueRange h;
  const cv::Rect box = box_in & cv::Rect(0, 0, depth_m.cols, depth_m.rows);
  if (box.area() == 0) return h;
  double sum = 0;
  for (const cv::Point& p : samples) {
    if (!box.contains(p)) continue;
    ++h.in_box;
    const float g = depth_m.at<float>(p);
    if (!(g > 0)) continue;
    sum += g;
    ++h.samples;
    h.sample_depths.push_back(g);
  }
  if (h.samples == 0) return h;
  h.g_h = sum / h.samples;
  h.lo = h.g_h - o.alpha_m, h.hi = h.g_h + o.alpha_m;
  // Box statistics over every valid pixel (two passes: mean, then population std).
  double s = 0;
  for (int y = box.y; y < box.br().y; ++y) {
    const float* d = depth_m.ptr<float>(y);
    for (int x = box.x; x < box.br().x; ++x)
      if (d[x] > 0) s += d[x], ++h.box_valid_px;
  }
  if (h.box_valid_px == 0) return h;
  h.mu_box = s / h.box_valid_px;
  double v = 0;
  for (int y = box.y; y < box.br().y; ++y) {
    const float* d = depth_m.ptr<float>(y);
    for (int x = box.x; x < box.br().x; ++x)
      if (d[x] > 0) v += (d[x] - h.mu_box) * (d[x] - h.mu_box);
  }
  h.sigma_box = std::sqrt(v / h.box_valid_px);
  const double screen = o.sigma_mult * h.sigma_box;
  for (int y = box.y; y < box.br().y; ++y) {
    const float* d = depth_m.ptr<float>(y);
    uint8_t* m = fused->ptr<uint8_t>(y);
    for (int x = box.x; x < box.br().x; ++x) {
      const double g = d[x];
      if (!(g > 0) || g < h.lo || g > h.hi || std::abs(g - h.mu_box) > screen) continue;
      m[x] = 255;
      ++h.fused_px;
    }
  }
  return h;
}

}  // namespace dynref::blur
