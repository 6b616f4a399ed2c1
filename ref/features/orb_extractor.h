// ORB feature extraction equivalent to ORB-SLAM2's ORBextractor (Mur-Artal & Tardos 2017,
// src/ORBextractor.cc): scale pyramid (8 levels, factor 1.2, features per level in geometric
// proportion), FAST with threshold 20 and a per-cell fallback to 7 on 30 px cells, quadtree
// distribution to the per-level budget (best response per node), intensity-centroid orientation
// (Rosin 1999), 256-bit rBRIEF on the 7x7 sigma-2 Gaussian-blurred level image with the learned
// pattern of orb_pattern.h. Keypoint coordinates are returned at level-0 scale.
//
// Determinism: ORB-SLAM2 breaks ties in the quadtree by sorting (size, node pointer) pairs; here
// ties are broken by node creation order instead (stable), which is otherwise the same rule.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "features/descriptor.h"

namespace dynref::features {

struct OrbOptions {
  int n_features = 1000;     // ORBextractor.nFeatures
  double scale_factor = 1.2; // ORBextractor.scaleFactor
  int n_levels = 8;          // ORBextractor.nLevels
  int ini_th_fast = 20;      // ORBextractor.iniThFAST
  int min_th_fast = 7;       // ORBextractor.minThFAST
  void Check() const;        // throws InputError naming the bad field
};

class OrbExtractor {
 public:
  explicit OrbExtractor(const OrbOptions& options);
  // grey: CV_8U. Returns keypoints (octave, angle in degrees, size, response set) and the
  // N x 32 CV_8U descriptors, ordered by level then by quadtree node as ORB-SLAM2.
  void Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors);

  // FAST grid rows, quadtree levels and descriptor chunks on up to n threads (core/parallel.h);
  // keypoints and descriptors are the same bytes for every n (issue 18).
  void set_threads(int n) { threads_ = n; }

  const OrbOptions& options() const { return options_; }
  const std::vector<float>& scale_factors() const { return scale_; }
  const std::vector<int>& features_per_level() const { return features_per_level_; }
  const std::vector<cv::Mat>& pyramid() const { return pyramid_; }

 private:
  void ComputePyramid(const cv::Mat& grey);
  void ComputeKeyPointsOctTree(std::vector<std::vector<cv::KeyPoint>>* all_keys);
  std::vector<cv::KeyPoint> DistributeOctTree(const std::vector<cv::KeyPoint>& to_distribute,
                                              int min_x, int max_x, int min_y, int max_y,
                                              int n_features) const;

  OrbOptions options_;
  std::vector<float> scale_, inv_scale_;
  std::vector<int> features_per_level_;
  std::vector<int> umax_;
  std::vector<cv::Mat> pyramid_;        // level images (views into bordered buffers)
  std::vector<cv::Mat> pyramid_border_; // bordered buffers (EDGE_THRESHOLD on each side)
  int threads_ = 1;
};

}  // namespace dynref::features
