// OpenCV SIFT as a backbone extractor; see sift_extractor.h.
#include "features/sift_extractor.h"

#include <algorithm>
#include <cmath>

namespace dynref::features {
namespace {

// 2^(1/3): one level per SIFT layer. 24 levels reach 2^8, beyond the coarsest octave of a
// 640 x 480 image (OpenCV builds log2(min(W, H)) - 2 octaves).
constexpr int kSiftLevels = 24;

}  // namespace

SiftExtractor::SiftExtractor(const SiftOptions& options) : options_(options) {
  sift_ = cv::SIFT::create(options_.n_features, options_.octave_layers, options_.contrast_threshold,
                           options_.edge_threshold, options_.sigma);
}

int SiftExtractor::Level(int packed_octave, int octave_layers, int n_levels) {
  // OpenCV packs octave (signed byte; -1 = the upsampled first octave) | layer << 8 | sub-layer << 16.
  int octave = packed_octave & 255;
  if (octave >= 128) octave -= 256;
  const int layer = (packed_octave >> 8) & 255;
  return std::clamp(octave * octave_layers + layer, 0, n_levels - 1);
}

void SiftExtractor::Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors) {
  keys->clear();
  cv::Mat d;
  sift_->detectAndCompute(grey, cv::noArray(), *keys, d);
  if (d.empty()) d = cv::Mat(0, 128, CV_32F);
  NormaliseRows(&d);
  for (cv::KeyPoint& kp : *keys) kp.octave = Level(kp.octave, options_.octave_layers, kSiftLevels);
  *descriptors = d;
}

DescriptorProfile SiftExtractor::profile() const {
  DescriptorProfile p;
  p.extractor = "sift";
  p.type = CV_32F;
  p.cols = 128;
  p.worst = 4;  // squared L2 of unit rows is at most 4 (at most 2 for SIFT's non-negative rows)
  // Gates in squared L2 of unit rows, placed where ORB-SLAM2's bit gates sit in ORB's distance
  // distributions (reports/epi-table2.md, nearest neighbours of exact synthetic correspondences):
  // ORB correct p75 49 / wrong p5-p25 38-62 bits -> TH_LOW 50; SIFT correct p75 0.13, wrong p25 0.29 -> 0.20.
  // TH_HIGH 100 bits is above ORB's wrong p95 (86) -> SIFT wrong p95 0.57 -> 0.60.
  // Relocalisation's 64 bits is near ORB's wrong p25 -> SIFT 0.30.
  p.th_low = 0.20f;
  p.th_high = 0.60f;
  p.th_reloc = 0.30f;
  p.oriented = true;
  p.n_levels = kSiftLevels;
  p.scale_factor = std::pow(2.0, 1.0 / options_.octave_layers);
  return p;
}

}  // namespace dynref::features
