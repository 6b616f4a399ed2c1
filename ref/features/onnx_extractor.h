// A SuperPoint-style ONNX network behind the KeypointExtractor interface (issue 17, Module B):
// users who bring a SuperPoint or ZippyPoint export name its two outputs in the config
// (backbone onnx_*). Input: 1 x 1 x H x W float grey in [0, 1] (H, W padded with zeros to
// multiples of 8). Decoding (DeTone et al. 2018, SuperPoint Sec. 3):
//   score map: 1 x 65 x H/8 x W/8 logits -> softmax over the 65 channels of a cell, the dustbin
//              (channel 64) dropped, channel c -> pixel (8 y + c / 8, 8 x + c % 8); or a
//              1 x 1 x H x W map used as it is;
//   keypoints: score > threshold, outside the border, greedy non-maximum suppression in
//              descending score (ties: row, then column) with a (2 r + 1)^2 window, best n kept;
//   descriptors: 1 x D x Hd x Wd map sampled bilinearly at each keypoint (pixel-centre
//              alignment: x_d = (u + 0.5) Wd / W - 0.5, clamped at the map's edges), then
//              L2-normalised, or packed by sign into D / 8 bytes (binary = ZippyPoint's head).
// Single scale and unoriented: octave 0, angle 0, a one-level profile (spec 004 E5).
#pragma once
#include <opencv2/dnn.hpp>

#include "features/keypoint_extractor.h"

namespace dynref::features {

// H x W CV_32F score image of a 1 x 65 x Hc x Wc (cell 8) or 1 x 1 x H x W network output.
// std::invalid_argument for any other shape.
cv::Mat DecodeScoreMap(const cv::Mat& output, int height, int width);
// Keypoints of a score image (response = score), best first.
std::vector<cv::KeyPoint> SelectKeypoints(const cv::Mat& scores, double threshold, int nms_radius, int border,
                                          int n_features);
// One row per keypoint from a 1 x D x Hd x Wd descriptor output over an H x W image.
cv::Mat SampleDescriptors(const cv::Mat& output, const std::vector<cv::KeyPoint>& keys, int height, int width,
                          bool binary);

class OnnxExtractor : public KeypointExtractor {
 public:
  explicit OnnxExtractor(const OnnxOptions& options);  // InputError naming the model file
  void Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors) override;
  DescriptorProfile profile() const override;

 private:
  OnnxOptions options_;
  cv::dnn::Net net_;
  int descriptor_dim_ = 0;  // learned at the first frame (profile() needs the width)
};

}  // namespace dynref::features
