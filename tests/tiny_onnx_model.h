// A small SuperPoint-shaped ONNX model built by the tests themselves (issue 17, Module B): the
// protobuf is written by hand (no onnx package on the machine), two Conv nodes on a
// 1 x 1 x H x W grey input:
//   scores (1 x 65 x H/8 x W/8): channel c < 64 of a cell = gain * (I(pixel c) - cell mean), the
//     dustbin a constant bias; after the softmax a cell's brightest pixel wins when it stands out,
//     a flat cell stays below 1 / (64 + e^bias) (0.014 for bias 2, under SuperPoint's 0.015);
//   descriptors (1 x D x H/8 x W/8): 16 x 16 kernels, stride 8, pad 4, Gaussian-smoothed random
//     weights from dynref's seeded Rng (a random-projection descriptor of the cell's surroundings).
#pragma once
#include <cstdint>
#include <string>

namespace dynref::test {

struct TinyModelSpec {
  int height = 480, width = 640;  // multiples of 8
  int descriptor_dim = 32;
  float score_gain = 20;
  float dustbin_bias = 2;
  uint64_t seed = 1;
};

// Writes the model to path (throws std::runtime_error when the file cannot be written).
void WriteTinySuperPoint(const std::string& path, const TinyModelSpec& spec = {});

}  // namespace dynref::test
