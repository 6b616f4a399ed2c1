// seed 004 Module A (Sec. 3.1): low-light enhancement of the grey image before feature
// extraction. The paper's displayed equations were lost in the extraction; the forms below are the
// spec's reconstructions (spec 004 step 1, E1):
//   a. CDF percentile clipping: I_lo = min{g : CDF(g) >= s}, I_hi = min{g : CDF(g) >= 1 - s};
//   b. Eq. (1) stretch: I_s = clip01((I - I_lo) / (I_hi - I_lo));
//   c. Eq. (2) locally weighted enhancement over a w x w window (mu_w, sigma_w):
//      W = alpha * (|I_s - mu_w| / (sigma_w + e0))^p,  E = clip01(mu_w + (1 + W) (I_s - mu_w));
//   d. Eq. (3) fitness (lost; the spec's standard metaheuristic form):
//      fit = ln(ln(sum |Sobel|)) * (n_edge / (H W)) * entropy(E);
//   e. two-scale fusion: I_f = w_ms * up(E(down(I_s))) + (1 - w_ms) * E(I_s);
//   f. CLAHE on I_f.
#pragma once
#include <opencv2/core.hpp>

#include <cstdint>

namespace dynref::epi {

// Smallest two-scale factor `down` (read_options.cpp says why).
constexpr double kMinEnhanceDown = 0.05;

struct EnhanceParams {
  double s = 0.01;            // CDF clipping proportion (not stated: 1 % / 99 %)
  int window = 7;             // w, odd (not stated)
  double alpha = 0.5;         // weight coefficient (optimised by BOA in the paper)
  double p = 1.0;             // weight exponent (optimised by BOA in the paper)
  double e0 = 0.01;           // contrast floor in W's denominator (not stated)
  double down = 0.5;          // two-scale down factor (not stated), in [kMinEnhanceDown, 1)
  double w_ms = 0.5;          // two-scale weight (not stated)
  double clahe_clip = 2.0;    // OpenCV common value (not stated)
  int clahe_tiles = 8;        // 8 x 8 tiles (not stated)
  double edge_threshold = 0.1;  // |Sobel| (intensity in [0, 1]) counted as an edge in the fitness (not stated)
  void Check() const;         // std::invalid_argument naming the field
};

struct StretchResult {
  cv::Mat stretched;          // CV_32F in [0, 1]
  double lo = 0, hi = 1;      // I_lo, I_hi in [0, 1]
  // The CDF at I_lo - 1/255 and I_lo (and at I_hi): cdf_lo_below < s <= cdf_lo (the trace's proof
  // of the percentile rule; the value below the first grey level is 0).
  double cdf_lo_below = 0, cdf_lo = 0, cdf_hi_below = 0, cdf_hi = 0;
};
// Full-image buffers of c and d kept between calls: the same bytes as fresh ones, no full-image
// allocation per call once sized (one workspace per image size).
struct EnhanceWorkspace {
  cv::Mat sq, mu, mu2;  // I^2 and the box means of I and I^2
  cv::Mat gx, gy, mags; // Sobel and (threads > 1) the gradient magnitudes
};
// a + b on a CV_8U grey image.
StretchResult CdfStretch(const cv::Mat& grey8, double s);
// threads (the run's --threads, not a parameter): the per-pixel work of c and d runs in row chunks
// side by side; sums stay in one fixed order, so the results are the same bytes for any count.
// c on CV_32F [0, 1].
cv::Mat LocalWeightedEnhance(const cv::Mat& stretched, const EnhanceParams& p, int threads = 1);
void LocalWeightedEnhance(const cv::Mat& stretched, const EnhanceParams& p, int threads, EnhanceWorkspace& ws,
                          cv::Mat& out);
// The statistics the fitness consumes (traced by epi.enhance: the fitness is recomputed from them).
struct FitnessTerms {
  double sobel_sum = 0;       // sum over pixels of |Sobel|
  int64_t edge_pixels = 0;    // pixels with |Sobel| > edge_threshold
  int64_t pixels = 0;
  double entropy = 0;         // bits, of the 256-bin histogram of E
};
// d: the fitness of an enhanced CV_32F [0, 1] image; -inf when it has no edges at all.
// `terms` (optional) receives the statistics (entropy 0 when the fitness is -inf).
double EnhancementFitness(const cv::Mat& enhanced, double edge_threshold, int threads = 1,
                          FitnessTerms* terms = nullptr);
double EnhancementFitness(const cv::Mat& enhanced, double edge_threshold, int threads, FitnessTerms* terms,
                          EnhanceWorkspace& ws);

struct EnhanceResult {
  cv::Mat grey8;              // CV_8U, what feature extraction sees
  double lo = 0, hi = 1;      // the stretch
  double fitness = 0;         // of E(I_s) at full scale
  StretchResult stretch;      // a + b (its CDF values; `stretched` released)
  FitnessTerms fitness_terms; // of `fitness`
  double mean_in = 0, mean_out = 0;  // mean grey in [0, 1] before and after
};
// What Enhance keeps between frames of one size (SequenceEnhancer owns one).
struct EnhanceBuffers {
  EnhanceWorkspace full, half;                // c and d at full and at the down scale
  cv::Mat enhanced, small, small_enhanced, up, fused, fused8;
};
// a-f on a CV_8U grey image.
EnhanceResult Enhance(const cv::Mat& grey8, const EnhanceParams& p, int threads = 1);
EnhanceResult Enhance(const cv::Mat& grey8, const EnhanceParams& p, int threads, EnhanceBuffers& buffers);

}  // namespace dynref::epi
