// Tiny ONNX "networks" with the exact output layouts of real detector / segmenter exports
// (YOLOv8 / YOLO11 detect and seg, torchvision Mask R-CNN, YOLACT), hand-encoded (no ONNX library):
// every output is a run of consecutive values of the flattened input blob, each run scaled and
// offset (value = scale * input + offset), reshaped to the output's shape and optionally
// upsampled (nearest, last two axes) so large prototype / mask planes need few input values.
// A test sets chosen pixels of the frame to make the "network" predict chosen boxes, scores,
// classes, coefficients and masks.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dynref::test {

struct LayoutSegment {
  int64_t length = 0;
  float scale = 1, offset = 0;
};

struct LayoutOutput {
  std::string name;
  std::vector<int64_t> shape;           // final shape
  std::vector<LayoutSegment> segments;  // cover shape's values / upsample^2, in order
  int upsample = 1;                     // nearest-neighbour factor on the last two axes (4-D only)
};

// Input "images" [1, 3, height, width]; outputs read the flattened input from position 0 on,
// one output after the other. std::invalid_argument when the segments do not fit.
void WriteTinyLayoutOnnx(const std::string& path, int height, int width, const std::vector<LayoutOutput>& outputs);

// Sets the pixel that becomes flat input position k of a blobFromImage(swapRB) / RGB-first blob:
// channel k / (w * h) is R, G, B = BGR index 2, 1, 0.
void SetFlatPixel(cv::Mat& bgr, int64_t k, int pixel);

}  // namespace dynref::test
