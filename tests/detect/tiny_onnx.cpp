#include "tiny_onnx.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace dynref::test {
namespace {

// Minimal protobuf encoding (wire types 0 = varint, 2 = length-delimited, 5 = fixed32).
struct Pb {
  std::string b;
  void Varint(uint64_t v) {
    while (v >= 0x80) {
      b.push_back(char((v & 0x7f) | 0x80));
      v >>= 7;
    }
    b.push_back(char(v));
  }
  Pb& Int(int field, int64_t v) {
    Varint(uint64_t(field) << 3);
    Varint(uint64_t(v));
    return *this;
  }
  Pb& Bytes(int field, const std::string& s) {
    Varint((uint64_t(field) << 3) | 2);
    Varint(s.size());
    b += s;
    return *this;
  }
  Pb& Msg(int field, const Pb& m) { return Bytes(field, m.b); }
};

Pb Int64Tensor(const std::string& name, const std::vector<int64_t>& values) {
  Pb t;
  t.Int(1, int64_t(values.size()));  // dims
  t.Int(2, 7);                       // INT64
  t.Bytes(8, name);
  std::string raw(values.size() * 8, '\0');
  std::memcpy(raw.data(), values.data(), raw.size());  // little-endian host (x86-64)
  t.Bytes(9, raw);
  return t;
}

Pb FloatTensor(const std::string& name, float value) {
  Pb t;
  t.Int(1, 1);
  t.Int(2, 1);  // FLOAT
  t.Bytes(8, name);
  std::string raw(4, '\0');
  std::memcpy(raw.data(), &value, 4);
  t.Bytes(9, raw);
  return t;
}

Pb Node(const std::string& op, const std::vector<std::string>& in, const std::string& out, int axis = -1) {
  Pb n;
  for (const auto& s : in) n.Bytes(1, s);
  n.Bytes(2, out);
  n.Bytes(3, out + "_node");
  n.Bytes(4, op);
  if (axis >= 0) {
    Pb a;
    a.Bytes(1, "axis");
    a.Int(3, axis);
    a.Int(20, 2);  // AttributeProto.INT
    n.Msg(5, a);
  }
  return n;
}

Pb ValueInfo(const std::string& name, const std::vector<int64_t>& shape) {
  Pb dims;
  for (int64_t d : shape) dims.Msg(1, Pb().Int(1, d));
  Pb tensor_type;
  tensor_type.Int(1, 1);  // FLOAT
  tensor_type.Msg(2, dims);
  Pb type;
  type.Msg(1, tensor_type);
  Pb v;
  v.Bytes(1, name);
  v.Msg(2, type);
  return v;
}

}  // namespace

void WriteTinyYoloSegOnnx(const std::string& path, int s) {
  const int64_t anchors = (s / 8) * (s / 8) + (s / 16) * (s / 16) + (s / 32) * (s / 32);
  const int64_t channels = 6, box_end = 4 * anchors, pred_end = channels * anchors;
  const int64_t proto_side = s / 4, proto_end = pred_end + proto_side * proto_side;
  Pb g;
  g.Msg(1, Node("Reshape", {"images", "shape_flat"}, "flat"));
  g.Msg(1, Node("Slice", {"flat", "zero", "box_end", "axis1"}, "box_raw"));
  g.Msg(1, Node("Mul", {"box_raw", "box_scale"}, "box"));
  g.Msg(1, Node("Slice", {"flat", "box_end", "pred_end", "axis1"}, "rest"));
  g.Msg(1, Node("Concat", {"box", "rest"}, "pred_flat", 1));
  g.Msg(1, Node("Reshape", {"pred_flat", "shape_pred"}, "output0"));
  g.Msg(1, Node("Slice", {"flat", "pred_end", "proto_end", "axis1"}, "proto_flat"));
  g.Msg(1, Node("Reshape", {"proto_flat", "shape_proto"}, "output1"));
  g.Bytes(2, "tiny_yolo_seg");
  g.Msg(5, Int64Tensor("shape_flat", {1, 3 * int64_t(s) * s}));
  g.Msg(5, Int64Tensor("zero", {0}));
  g.Msg(5, Int64Tensor("axis1", {1}));
  g.Msg(5, Int64Tensor("box_end", {box_end}));
  g.Msg(5, Int64Tensor("pred_end", {pred_end}));
  g.Msg(5, Int64Tensor("proto_end", {proto_end}));
  g.Msg(5, Int64Tensor("shape_pred", {1, channels, anchors}));
  g.Msg(5, Int64Tensor("shape_proto", {1, 1, proto_side, proto_side}));
  g.Msg(5, FloatTensor("box_scale", float(kTinyBoxScale)));
  g.Msg(11, ValueInfo("images", {1, 3, s, s}));
  g.Msg(12, ValueInfo("output0", {1, channels, anchors}));
  g.Msg(12, ValueInfo("output1", {1, 1, proto_side, proto_side}));
  Pb model;
  model.Int(1, 7);  // ir_version
  model.Bytes(2, "dynref-test");
  model.Msg(7, g);
  Pb opset;
  opset.Bytes(1, "");
  opset.Int(2, 12);
  model.Msg(8, opset);
  std::ofstream out(path, std::ios::binary);
  out.write(model.b.data(), std::streamsize(model.b.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace dynref::test
