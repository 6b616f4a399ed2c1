// OpenCV SIFT behind the KeypointExtractor interface (issue 17, Module B float path).
#pragma once
#include <opencv2/features2d.hpp>

#include "features/keypoint_extractor.h"

namespace dynref::features {

class SiftExtractor : public KeypointExtractor {
 public:
  explicit SiftExtractor(const SiftOptions& options);
  // Keypoints in OpenCV's order; octave = 3 * SIFT octave + layer, i.e. the level of a
  // 2^(1/3) pyramid (the upsampled octave -1 goes to level 0); rows L2-normalised.
  void Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors) override;
  DescriptorProfile profile() const override;
  // Pyramid level of an OpenCV SIFT keypoint's packed octave (clamped to [0, n_levels - 1]).
  static int Level(int packed_octave, int octave_layers, int n_levels);

 private:
  SiftOptions options_;
  cv::Ptr<cv::SIFT> sift_;
};

}  // namespace dynref::features
