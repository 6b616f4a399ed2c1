// The tiny SuperPoint (tests/onnx_protobuf.h encodes it); see the header.
#include "tiny_onnx_model.h"

#include <stdexcept>
#include <vector>

#include "core/rng.h"
#include "onnx_protobuf.h"

namespace dynref::test {

using namespace onnx;

void WriteTinySuperPoint(const std::string& path, const TinyModelSpec& s) {
  if (s.height % 8 != 0 || s.width % 8 != 0) throw std::runtime_error("tiny model: H and W must be multiples of 8");
  // Score head: 65 x 1 x 8 x 8.
  std::vector<float> ws(65 * 64, 0.f), bs(65, 0.f);
  for (int c = 0; c < 64; ++c)
    for (int p = 0; p < 64; ++p) ws[static_cast<size_t>(c * 64 + p)] = s.score_gain * ((p == c ? 1.f : 0.f) - 1.f / 64);
  bs[64] = s.dustbin_bias;
  // Descriptor head: D x 1 x 16 x 16, white noise smoothed by a 5 x 5 binomial kernel.
  const int D = s.descriptor_dim, K = 16;
  Rng rng(s.seed, "tiny-superpoint");
  std::vector<float> wd(static_cast<size_t>(D * K * K)), bd(static_cast<size_t>(D), 0.f);
  const double bin[5] = {1, 4, 6, 4, 1};
  for (int c = 0; c < D; ++c) {
    std::vector<double> noise(static_cast<size_t>((K + 4) * (K + 4)));
    for (double& n : noise) n = rng.Gaussian();
    for (int y = 0; y < K; ++y)
      for (int x = 0; x < K; ++x) {
        double acc = 0;
        for (int dy = 0; dy < 5; ++dy)
          for (int dx = 0; dx < 5; ++dx) acc += bin[dy] * bin[dx] * noise[static_cast<size_t>((y + dy) * (K + 4) + x + dx)];
        wd[static_cast<size_t>((c * K + y) * K + x)] = static_cast<float>(acc / 256.0);
      }
  }
  const int64_t hc = s.height / 8, wc = s.width / 8;
  Pb graph;
  auto conv = [](const std::string& w, const std::string& bias, const std::string& out, int64_t kernel, int64_t pad) {
    return Node("Conv", {"image", w, bias}, out,
                {IntsAttribute("kernel_shape", {kernel, kernel}), IntsAttribute("strides", {8, 8}),
                 IntsAttribute("pads", {pad, pad, pad, pad})});
  };
  graph.Msg(1, conv("w_score", "b_score", "scores", 8, 0));
  graph.Msg(1, conv("w_desc", "b_desc", "descriptors", K, 4));
  graph.Bytes(2, "tiny_superpoint");
  graph.Msg(5, FloatTensor("w_score", {65, 1, 8, 8}, ws));
  graph.Msg(5, FloatTensor("b_score", {65}, bs));
  graph.Msg(5, FloatTensor("w_desc", {D, 1, K, K}, wd));
  graph.Msg(5, FloatTensor("b_desc", {D}, bd));
  graph.Msg(11, ValueInfo("image", {1, 1, s.height, s.width}));
  graph.Msg(12, ValueInfo("scores", {1, 65, hc, wc}));
  graph.Msg(12, ValueInfo("descriptors", {1, D, hc, wc}));
  WriteModel(graph, 11, "dynref tests", path);
}

}  // namespace dynref::test
