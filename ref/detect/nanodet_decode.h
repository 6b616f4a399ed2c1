// Decoding of NanoDet's GFL head (models/README.md): per stride level s in {8, 16, 32} a class
// score tensor [1, N, 80] (already sigmoid) and a box tensor [1, N, 4 * (reg_max + 1)] holding,
// for the sides left, top, right, bottom, a discrete distribution over distances 0..reg_max
// (Generalized Focal Loss, Li et al. 2020, "Distribution Focal Loss": the distance is the
// expectation sum_k softmax(bins)_k * k, in units of the stride).
#pragma once
#include <opencv2/core.hpp>
#include <vector>

#include "detect/candidates.h"

namespace dynref::detect {

struct NanodetLevel {
  int stride = 8;
  cv::Mat scores;  // CV_32F, N x num_classes (any leading singleton dims flattened)
  cv::Mat boxes;   // CV_32F, N x 4 * (reg_max + 1)
};

struct NanodetDecodeOptions {
  int input_size = 416;          // square network input, pixels
  int reg_max = 10;              // bins per side = reg_max + 1 = 11
  double score_threshold = 0.3;  // models/README.md: persons 0.36-0.38 on TUM frames
  // Image size the boxes are scaled back to (plain resize, no letterbox).
  int image_width = 416, image_height = 416;
  // Cell centre = (column + cell_offset, row + cell_offset) * stride. NanoDet's GFL head
  // (nanodet gfl_head.py, get_single_level_center_point) and the TF.js port this model comes from
  // (human src/object/nanodet.ts) use 0.5; models/README.md states 0, but on the darknet photos
  // 0 shifts every box up-left by half a stride (mean edge error 9.1 px vs 3.0 px with 0.5 over
  // four hand-measured objects, see ref/detect/README.md), so 0.5 is the default.
  double cell_offset = 0.5;
};

// Candidates (best class per cell above threshold), boxes in image pixels, clipped, anchor =
// running cell index over the levels in the given order. Throws std::invalid_argument for
// tensors whose shapes do not fit the options.
std::vector<Candidate> DecodeNanodet(const std::vector<NanodetLevel>& levels,
                                     const NanodetDecodeOptions& options);

// Expected distance of one side: sum_k softmax(logits)_k * k (numerically stable softmax).
double DistributionExpectation(const float* logits, int bins);

// Reshapes a network output [1, N, C] (or N x C) to an N x C CV_32F header (no copy).
cv::Mat AsRows(const cv::Mat& blob);

}  // namespace dynref::detect
