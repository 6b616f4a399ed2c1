#include "dynamic/epi/enhance_terms.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/parallel.h"
#include "dynamic/epi/enhance_pixel.h"

namespace dynref::epi {

namespace {

// Distinct values of `ratio` ascending, and each pixel's index among them.
void Distinct(const std::vector<double>& ratio, std::vector<double>* values, std::vector<uint32_t>* id) {
  std::vector<uint32_t> order(ratio.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return ratio[a] < ratio[b]; });
  values->clear();
  id->assign(ratio.size(), 0);
  for (uint32_t i : order) {
    if (values->empty() || values->back() != ratio[i]) values->push_back(ratio[i]);
    (*id)[i] = uint32_t(values->size() - 1);
  }
}

}  // namespace

EnhanceTerms::EnhanceTerms(const cv::Mat& I, const EnhanceParams& p, int threads) : rows_(I.rows), cols_(I.cols) {
  CV_Assert(I.type() == CV_32F);
  const cv::Size k(p.window, p.window);
  cv::Mat mu, mu2, sq;
  cv::boxFilter(I, mu, CV_32F, k, cv::Point(-1, -1), true, cv::BORDER_REFLECT_101);
  cv::multiply(I, I, sq);
  cv::boxFilter(sq, mu2, CV_32F, k, cv::Point(-1, -1), true, cv::BORDER_REFLECT_101);
  const size_t n = I.total();
  mu_.resize(n), d_.resize(n), side_.resize(n);
  std::vector<double> ratio(n);
  ParallelForEach(size_t(rows_), threads, [&](size_t row) {
    const int y = int(row);
    const float* i = I.ptr<float>(y);
    const float* m = mu.ptr<float>(y);
    const float* m2 = mu2.ptr<float>(y);
    for (int x = 0; x < cols_; ++x) {
      const size_t j = row * size_t(cols_) + size_t(x);
      mu_[j] = m[x];
      ratio[j] = pixel::ContrastRatio(i[x], m[x], m2[x], p.e0, &d_[j]);
      side_[j] = pixel::Saturation(m[x], d_[j]);
    }
  }, 16);
  Distinct(ratio, &ratios_, &ratio_id_);
  inside_.assign(ratios_.size(), 0);
  for (size_t j = 0; j < n; ++j)
    if (side_[j] == pixel::kInside) inside_[ratio_id_[j]] = 1;
  powers_.resize(ratios_.size());
}

void EnhanceTerms::Apply(double alpha, double p, cv::Mat& out, int threads) {
  const bool bounded = alpha > 0;  // pixel::Saturation holds only then
  ParallelForEach(ratios_.size(), threads, [&](size_t k) {
    if (!bounded || inside_[k]) powers_[k] = std::pow(ratios_[k], p);
  }, 4096);
  out.create(rows_, cols_, CV_32F);
  ParallelForEach(size_t(rows_), threads, [&](size_t row) {
    float* o = out.ptr<float>(int(row));
    for (int x = 0; x < cols_; ++x) {
      const size_t j = row * size_t(cols_) + size_t(x);
      const auto side = bounded ? pixel::Side(side_[j]) : pixel::kInside;
      o[x] = side != pixel::kInside ? pixel::BoundOf(side) : pixel::Weighted(mu_[j], d_[j], alpha * powers_[ratio_id_[j]]);
    }
  }, 16);
}

}  // namespace dynref::epi
