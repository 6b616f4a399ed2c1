// Decoding of raw YOLOv8 / YOLO11 (Ultralytics) head outputs exported to ONNX, for the
// `onnx-yolo` source. Detect models have one output [1, 4 + nc, A]; seg models add mask
// coefficients, [1, 4 + nc + nm, A], and a prototype output [1, nm, H/4, W/4]. A = number of
// anchor points = sum over strides 8, 16, 32 of (S / stride)^2 (8400 for S = 640). Box rows are
// (cx, cy, w, h) in letterboxed input pixels; class scores are already sigmoid (no objectness).
// An export that transposes to [1, A, 4 + nc (+ nm)] is accepted too.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

#include "detect/candidates.h"

namespace dynref::detect {

// Ultralytics letterbox: uniform scale to fit S x S, centred, padded with grey 114.
struct Letterbox {
  int input_size = 640;
  double scale = 1;
  int pad_left = 0, pad_top = 0;
  int scaled_width = 640, scaled_height = 640;
  int image_width = 640, image_height = 640;
};
Letterbox ComputeLetterbox(int image_width, int image_height, int input_size);
cv::Mat ApplyLetterbox(const cv::Mat& bgr, const Letterbox& lb);  // CV_8UC3, S x S

// Anchor count for a square input with strides 8, 16, 32.
int YoloAnchorCount(int input_size);

// Prediction tensor rearranged to channels x anchors (CV_32F, contiguous).
struct YoloPredictions {
  cv::Mat channels_by_anchor;  // (4 + nc + nm) x A
  int num_classes = 0;
  int num_mask_coeffs = 0;
};
// num_mask_coeffs: channel count of the prototype tensor (0 for detect models). Throws
// std::invalid_argument when the shape matches neither orientation.
YoloPredictions ArrangeYoloPredictions(const cv::Mat& output, int input_size, int num_mask_coeffs);

// Candidates above score_threshold (best class per anchor), boxes mapped back to the image
// through the letterbox and clipped; anchor = column index.
std::vector<Candidate> DecodeYoloBoxes(const YoloPredictions& pred, const Letterbox& lb,
                                       double score_threshold);

// Instance mask of a seg model: sigmoid(coeffs . protos) at prototype resolution, bilinearly
// resized to the letterboxed input, un-letterboxed to the image, thresholded at 0.5 and cropped to
// the candidate's box (as Ultralytics' process_mask). protos: [1, nm, h, w] or nm x h x w.
// Returns CV_8U 0/255 of the image size.
cv::Mat DecodeYoloMask(const YoloPredictions& pred, const cv::Mat& protos, const Candidate& c,
                       const Letterbox& lb);

}  // namespace dynref::detect
