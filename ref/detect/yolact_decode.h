// Decoding of a YOLACT ONNX export (Bolya et al. 2019, "YOLACT: Real-time Instance Segmentation";
// code dbolya/yolact, yolact_base_config with max_size 550). Layout of torch.onnx.export of
// Yolact.forward without its Detect layer (as the public OpenCV-DNN / onnxruntime ports export it;
// shapes from yolact.py with a 550 input):
//   loc   [1, P, 4]   box offsets against the priors (layers/box_utils.py decode, variances 0.1, 0.2)
//   conf  [1, P, C+1] softmax class confidences, column 0 = background (C = 80 for COCO)
//   mask  [1, P, k]   mask coefficients (tanh), k = 32
//   proto [1, h, w, k] prototypes, channels last (138 x 138 at 550)
// P = 3 priors per cell over the FPN levels P3..P7 (69, 35, 18, 9, 5 cells for 550; 19248 in all).
// Priors (yolact.py PredictionModule.make_priors, yolact_base: use_pixel_scales, use_square_anchors,
// preapply_sqrt False): cell centre ((i + 0.5) / conv_w, (j + 0.5) / conv_h), scales 24, 48, 96,
// 192, 384 px for the five levels, aspect ratios 1, 1/2, 2: w = h = scale * sqrt(ar) / 550
// (square by the "backward compatibility" bug the config keeps). Boxes are normalised to the
// 550 x 550 resized input (no letterbox), so they map to the image by its width and height.
// Input: image resized to 550 x 550, RGB, (pixel - mean) / std with BGR means 103.94, 116.78,
// 123.68 and stds 57.38, 57.12, 58.40 (data/config.py MEANS / STD).
#pragma once
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/candidates.h"

namespace dynref::detect {

struct YolactLayout {
  int input_size = 550;
  std::vector<int> conv_sizes = {69, 35, 18, 9, 5};     // cells per side of each FPN level
  std::vector<double> scales = {24, 48, 96, 192, 384};  // prior size per level, input pixels
  std::vector<double> aspect_ratios = {1, 0.5, 2};
  double variance_center = 0.1, variance_size = 0.2;
};

// Priors (cx, cy, w, h), normalised, P x 4 CV_32F in YOLACT's order (level, row, column, ratio).
// For input sizes other than 550 the conv sizes follow yolact.py: ceil of successive halvings of
// input / 8 (std::invalid_argument for input < 32).
cv::Mat YolactPriors(const YolactLayout& layout);
YolactLayout YolactLayoutForInput(int input_size);

struct YolactOutputs {
  cv::Mat loc, conf, coeffs;  // P x 4, P x (C + 1), P x k (CV_32F)
  cv::Mat proto;              // h x w x k as a (h * w) x k CV_32F matrix
  int proto_h = 0, proto_w = 0;
};
// The four outputs by name (loc, conf, mask, proto) or by shape (proto is the 4-D one; loc has 4
// columns, mask k = proto channels, conf the rest). std::invalid_argument naming what is wrong,
// including P != the prior count of the input size.
YolactOutputs ArrangeYolactOutputs(const std::vector<cv::Mat>& outs, const std::vector<std::string>& names,
                                   int prior_count);

// Candidates whose best non-background confidence > threshold; class_id = column - 1; boxes in
// image pixels (clipped); anchor = prior index.
std::vector<Candidate> DecodeYolactBoxes(const YolactOutputs& out, const cv::Mat& priors, cv::Size image,
                                         double threshold, const YolactLayout& layout);

// Instance mask (layers/output_utils.py postprocess): sigmoid(proto . coeffs) at prototype
// resolution, cropped to the box there, resized bilinearly to the image, > 0.5. CV_8U 0/255.
cv::Mat DecodeYolactMask(const YolactOutputs& out, const Candidate& c, cv::Size image);

// The network input: 1 x 3 x S x S CV_32F blob as data/config.py normalises it.
cv::Mat YolactBlob(const cv::Mat& bgr, int input_size);

}  // namespace dynref::detect
