// Eq. (2) (enhance.h c) for many (alpha, p) on one image: the first frame's BOA evaluates 620 of
// them. mu_w, sigma_w, d = I_s - mu_w and the contrast ratio |d| / (sigma_w + e0) do not depend on
// (alpha, p), so they are computed once; each evaluation raises every distinct ratio to p once and
// skips the pixels whose clamp does not depend on W (pixel::Saturation). Apply writes the same
// bytes as LocalWeightedEnhance with those (alpha, p).
#pragma once
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "dynamic/epi/enhance.h"

namespace dynref::epi {

class EnhanceTerms {
 public:
  // window and e0 of `p` (alpha and p are Apply's); `stretched` CV_32F.
  EnhanceTerms(const cv::Mat& stretched, const EnhanceParams& p, int threads = 1);
  // `out` (re)sized to the image, CV_32F. threads: the run's --threads, same bytes for any count.
  void Apply(double alpha, double p, cv::Mat& out, int threads = 1);
  size_t distinct_ratios() const { return ratios_.size(); }

 private:
  int rows_ = 0, cols_ = 0;
  std::vector<float> mu_;           // per pixel, row-major
  std::vector<double> d_;           // I_s - mu_w
  std::vector<uint32_t> ratio_id_;  // index into ratios_
  std::vector<uint8_t> side_;       // pixel::Side
  std::vector<double> ratios_;      // distinct contrast ratios, ascending
  std::vector<uint8_t> inside_;     // ratios_[k] belongs to a pixel that is kInside
  std::vector<double> powers_;      // ratios_[k]^p of the last Apply
};

}  // namespace dynref::epi
