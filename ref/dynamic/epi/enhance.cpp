#include "dynamic/epi/enhance.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/parallel.h"
#include "dynamic/epi/enhance_pixel.h"

namespace dynref::epi {

void EnhanceParams::Check() const {
  if (!(s >= 0 && s < 0.5)) throw std::invalid_argument("s must be in [0, 0.5)");
  if (window < 3 || window % 2 == 0) throw std::invalid_argument("window must be odd and >= 3");
  if (!(alpha >= 0)) throw std::invalid_argument("alpha must be >= 0");
  if (!(p > 0)) throw std::invalid_argument("p must be > 0");
  if (!(e0 > 0)) throw std::invalid_argument("e0 must be > 0");
  if (!(down >= kMinEnhanceDown && down < 1))
    throw std::invalid_argument("down must be in [0.05, 1)");  // kMinEnhanceDown
  if (!(w_ms >= 0 && w_ms <= 1)) throw std::invalid_argument("w_ms must be in [0, 1]");
  if (!(clahe_clip > 0)) throw std::invalid_argument("clahe_clip must be > 0");
  if (clahe_tiles < 1) throw std::invalid_argument("clahe_tiles must be >= 1");
  if (!(edge_threshold > 0)) throw std::invalid_argument("edge_threshold must be > 0");
}

StretchResult CdfStretch(const cv::Mat& grey8, double s) {
  CV_Assert(grey8.type() == CV_8U);
  std::array<int64_t, 256> hist{};
  for (int y = 0; y < grey8.rows; ++y) {
    const uint8_t* r = grey8.ptr<uint8_t>(y);
    for (int x = 0; x < grey8.cols; ++x) ++hist[r[x]];
  }
  const double n = double(grey8.total());
  int lo = 0, hi = 255;
  int64_t cum = 0;
  bool have_lo = false, have_hi = false;
  double below = 0, cdf_lo_below = 0, cdf_lo = 0, cdf_hi_below = 0, cdf_hi = 0;
  for (int g = 0; g < 256 && !(have_lo && have_hi); ++g) {
    cum += hist[size_t(g)];
    const double cdf = double(cum) / n;
    if (!have_lo && cdf >= s) lo = g, have_lo = true, cdf_lo_below = below, cdf_lo = cdf;
    if (!have_hi && cdf >= 1.0 - s) hi = g, have_hi = true, cdf_hi_below = below, cdf_hi = cdf;
    below = cdf;
  }
  StretchResult r;
  r.cdf_lo_below = cdf_lo_below, r.cdf_lo = cdf_lo, r.cdf_hi_below = cdf_hi_below, r.cdf_hi = cdf_hi;
  r.lo = lo / 255.0;
  r.hi = hi / 255.0;
  grey8.convertTo(r.stretched, CV_32F, 1.0 / 255.0);
  if (hi > lo) {
    r.stretched = (r.stretched - r.lo) / (r.hi - r.lo);
    cv::min(cv::max(r.stretched, 0.0), 1.0, r.stretched);
  }
  return r;
}

namespace {

// The w x w box means of I and of I^2 (c) into the workspace.
void BoxMeans(const cv::Mat& I, int window, EnhanceWorkspace& ws) {
  const cv::Size k(window, window);
  cv::boxFilter(I, ws.mu, CV_32F, k, cv::Point(-1, -1), true, cv::BORDER_REFLECT_101);
  cv::multiply(I, I, ws.sq);  // what I.mul(I) evaluates to
  cv::boxFilter(ws.sq, ws.mu2, CV_32F, k, cv::Point(-1, -1), true, cv::BORDER_REFLECT_101);
}

}  // namespace

void LocalWeightedEnhance(const cv::Mat& I, const EnhanceParams& p, int threads, EnhanceWorkspace& ws, cv::Mat& out) {
  CV_Assert(I.type() == CV_32F);
  BoxMeans(I, p.window, ws);
  out.create(I.size(), CV_32F);
  const bool bounded = p.alpha > 0;  // pixel::Saturation may decide the clamp without pow
  ParallelForEach(size_t(I.rows), threads, [&](size_t row) {
    const int y = int(row);
    const float* i = I.ptr<float>(y);
    const float* m = ws.mu.ptr<float>(y);
    const float* m2 = ws.mu2.ptr<float>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < I.cols; ++x) {
      double d;
      const double ratio = pixel::ContrastRatio(i[x], m[x], m2[x], p.e0, &d);
      const pixel::Side side = bounded ? pixel::Saturation(m[x], d) : pixel::kInside;
      o[x] = side != pixel::kInside ? pixel::BoundOf(side) : pixel::Weighted(m[x], d, p.alpha * std::pow(ratio, p.p));
    }
  }, 16);
}

cv::Mat LocalWeightedEnhance(const cv::Mat& I, const EnhanceParams& p, int threads) {
  EnhanceWorkspace ws;
  cv::Mat out;
  LocalWeightedEnhance(I, p, threads, ws, out);
  return out;
}

namespace {

// sum |Sobel|, the edge count and the 256-bin histogram of E in pixel order. One thread: the
// magnitudes inline; more: magnitudes by rows into ws.mags first (the same doubles), then one sum.
void GradientSums(const cv::Mat& E, double edge_threshold, int threads, EnhanceWorkspace& ws, double* sum,
                  int64_t* edges, std::array<int64_t, 256>* hist) {
  const auto magnitude = [&](int y, int x) {
    const float a = ws.gx.ptr<float>(y)[x], b = ws.gy.ptr<float>(y)[x];
    return std::sqrt(double(a) * a + double(b) * b);
  };
  if (threads > 1) {
    ws.mags.create(E.size(), CV_64F);
    ParallelForEach(size_t(E.rows), threads, [&](size_t row) {
      double* m = ws.mags.ptr<double>(int(row));
      for (int x = 0; x < E.cols; ++x) m[x] = magnitude(int(row), x);
    }, 16);
  }
  for (int y = 0; y < E.rows; ++y) {
    const float* a = ws.gx.ptr<float>(y);
    const float* b = ws.gy.ptr<float>(y);
    const double* mags = threads > 1 ? ws.mags.ptr<double>(y) : nullptr;
    const float* e = E.ptr<float>(y);
    for (int x = 0; x < E.cols; ++x) {
      const double m = mags != nullptr ? mags[x] : std::sqrt(double(a[x]) * a[x] + double(b[x]) * b[x]);
      *sum += m;
      *edges += m > edge_threshold;
      ++(*hist)[size_t(std::clamp(int(e[x] * 255.0f + 0.5f), 0, 255))];
    }
  }
}

}  // namespace

double EnhancementFitness(const cv::Mat& E, double edge_threshold, int threads, FitnessTerms* terms,
                          EnhanceWorkspace& ws) {
  cv::Sobel(E, ws.gx, CV_32F, 1, 0, 3, 1, 0, cv::BORDER_REFLECT_101);
  cv::Sobel(E, ws.gy, CV_32F, 0, 1, 3, 1, 0, cv::BORDER_REFLECT_101);
  double sum = 0;
  int64_t edges = 0;
  std::array<int64_t, 256> hist{};
  GradientSums(E, edge_threshold, threads, ws, &sum, &edges, &hist);
  if (terms != nullptr) *terms = FitnessTerms{sum, edges, int64_t(E.total()), 0.0};
  if (!(sum > std::exp(1.0)) || edges == 0) return -std::numeric_limits<double>::infinity();
  const double n = double(E.total());
  double entropy = 0;
  for (int64_t h : hist)
    if (h > 0) entropy -= (double(h) / n) * std::log2(double(h) / n);
  if (terms != nullptr) terms->entropy = entropy;
  return std::log(std::log(sum)) * (double(edges) / n) * entropy;
}

double EnhancementFitness(const cv::Mat& E, double edge_threshold, int threads, FitnessTerms* terms) {
  EnhanceWorkspace ws;
  return EnhancementFitness(E, edge_threshold, threads, terms, ws);
}

EnhanceResult Enhance(const cv::Mat& grey8, const EnhanceParams& p, int threads, EnhanceBuffers& b) {
  EnhanceResult r;
  const StretchResult st = CdfStretch(grey8, p.s);
  r.lo = st.lo, r.hi = st.hi;
  LocalWeightedEnhance(st.stretched, p, threads, b.full, b.enhanced);
  r.fitness = EnhancementFitness(b.enhanced, p.edge_threshold, threads, &r.fitness_terms, b.full);
  r.stretch = st;
  r.stretch.stretched = cv::Mat();
  cv::resize(st.stretched, b.small, cv::Size(), p.down, p.down, cv::INTER_AREA);
  LocalWeightedEnhance(b.small, p, threads, b.half, b.small_enhanced);
  cv::resize(b.small_enhanced, b.up, b.enhanced.size(), 0, 0, cv::INTER_LINEAR);
  b.fused = p.w_ms * b.up + (1.0 - p.w_ms) * b.enhanced;
  b.fused.convertTo(b.fused8, CV_8U, 255.0);
  const cv::Ptr<cv::CLAHE> clahe = cv::createCLAHE(p.clahe_clip, cv::Size(p.clahe_tiles, p.clahe_tiles));
  clahe->apply(b.fused8, r.grey8);
  r.mean_in = cv::mean(grey8)[0] / 255.0;
  r.mean_out = cv::mean(r.grey8)[0] / 255.0;
  return r;
}

EnhanceResult Enhance(const cv::Mat& grey8, const EnhanceParams& p, int threads) {
  EnhanceBuffers b;
  return Enhance(grey8, p, threads, b);
}

}  // namespace dynref::epi
