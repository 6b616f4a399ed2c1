// Hand-written ONNX protobuf (onnx.proto field numbers) of the tiny SuperPoint; see the header.
#include "tiny_onnx_model.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "core/rng.h"

namespace dynref::test {
namespace {

// Protobuf wire format: varints, keys (field << 3 | wire type) and length-delimited fields.
struct Pb {
  std::string b;
  void Varint(uint64_t v) {
    while (v >= 0x80) b.push_back(static_cast<char>((v & 0x7F) | 0x80)), v >>= 7;
    b.push_back(static_cast<char>(v));
  }
  void Key(int field, int wire) { Varint(static_cast<uint64_t>(field) << 3 | static_cast<uint64_t>(wire)); }
  void Int(int field, int64_t v) { Key(field, 0), Varint(static_cast<uint64_t>(v)); }
  void Bytes(int field, const std::string& s) { Key(field, 2), Varint(s.size()), b += s; }
  void Msg(int field, const Pb& m) { Bytes(field, m.b); }
};

// TensorProto: dims 1, data_type 2 (FLOAT = 1), name 8, raw_data 9.
Pb Tensor(const std::string& name, const std::vector<int64_t>& dims, const std::vector<float>& v) {
  Pb t;
  for (int64_t d : dims) t.Int(1, d);
  t.Int(2, 1);
  t.Bytes(8, name);
  std::string raw(v.size() * 4, '\0');
  std::memcpy(raw.data(), v.data(), raw.size());  // little-endian floats
  t.Bytes(9, raw);
  return t;
}

// ValueInfoProto: name 1, type 2 -> TypeProto.tensor_type 1 -> elem_type 1, shape 2 -> dim 1 -> dim_value 1.
Pb ValueInfo(const std::string& name, const std::vector<int64_t>& dims) {
  Pb shape;
  for (int64_t d : dims) {
    Pb dim;
    dim.Int(1, d);
    shape.Msg(1, dim);
  }
  Pb tensor;
  tensor.Int(1, 1);
  tensor.Msg(2, shape);
  Pb type;
  type.Msg(1, tensor);
  Pb vi;
  vi.Bytes(1, name);
  vi.Msg(2, type);
  return vi;
}

// AttributeProto with INTS (name 1, ints 8, type 20 = INTS (7)).
Pb Ints(const std::string& name, const std::vector<int64_t>& v) {
  Pb a;
  a.Bytes(1, name);
  for (int64_t x : v) a.Int(8, x);
  a.Int(20, 7);
  return a;
}

// NodeProto Conv: input 1, output 2, name 3, op_type 4, attribute 5.
Pb Conv(const std::string& name, const std::string& in, const std::string& w, const std::string& bias,
        const std::string& out, int kernel, int stride, int pad) {
  Pb n;
  n.Bytes(1, in), n.Bytes(1, w), n.Bytes(1, bias);
  n.Bytes(2, out);
  n.Bytes(3, name);
  n.Bytes(4, "Conv");
  n.Msg(5, Ints("kernel_shape", {kernel, kernel}));
  n.Msg(5, Ints("strides", {stride, stride}));
  n.Msg(5, Ints("pads", {pad, pad, pad, pad}));
  return n;
}

}  // namespace

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
  graph.Msg(1, Conv("score_head", "image", "w_score", "b_score", "scores", 8, 8, 0));
  graph.Msg(1, Conv("descriptor_head", "image", "w_desc", "b_desc", "descriptors", K, 8, 4));
  graph.Bytes(2, "tiny_superpoint");
  graph.Msg(5, Tensor("w_score", {65, 1, 8, 8}, ws));
  graph.Msg(5, Tensor("b_score", {65}, bs));
  graph.Msg(5, Tensor("w_desc", {D, 1, K, K}, wd));
  graph.Msg(5, Tensor("b_desc", {D}, bd));
  graph.Msg(11, ValueInfo("image", {1, 1, s.height, s.width}));
  graph.Msg(12, ValueInfo("scores", {1, 65, hc, wc}));
  graph.Msg(12, ValueInfo("descriptors", {1, D, hc, wc}));
  Pb opset;
  opset.Bytes(1, "");
  opset.Int(2, 11);
  Pb model;
  model.Int(1, 7);  // ir_version
  model.Bytes(2, "dynref tests");
  model.Msg(7, graph);
  model.Msg(8, opset);
  std::ofstream out(path, std::ios::binary);
  out.write(model.b.data(), static_cast<std::streamsize>(model.b.size()));
  if (!out) throw std::runtime_error("tiny model: cannot write " + path);
}

}  // namespace dynref::test
