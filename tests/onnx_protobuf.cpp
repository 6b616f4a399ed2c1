// Hand-encoded ONNX protobuf; see onnx_protobuf.h.
#include "onnx_protobuf.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace dynref::test::onnx {

void Pb::Varint(uint64_t v) {
  while (v >= 0x80) {
    b.push_back(static_cast<char>((v & 0x7f) | 0x80));
    v >>= 7;
  }
  b.push_back(static_cast<char>(v));
}

Pb& Pb::Int(int field, int64_t v) {
  Varint(static_cast<uint64_t>(field) << 3);
  Varint(static_cast<uint64_t>(v));
  return *this;
}

Pb& Pb::Bytes(int field, const std::string& s) {
  Varint((static_cast<uint64_t>(field) << 3) | 2);
  Varint(s.size());
  b += s;
  return *this;
}

namespace {

// TensorProto: dims 1, data_type 2, name 8, raw_data 9 (little-endian host, x86-64).
Pb Tensor(const std::string& name, const std::vector<int64_t>& dims, int data_type, const void* data, size_t bytes) {
  Pb t;
  for (int64_t d : dims) t.Int(1, d);
  t.Int(2, data_type);
  t.Bytes(8, name);
  std::string raw(bytes, '\0');
  std::memcpy(raw.data(), data, bytes);
  t.Bytes(9, raw);
  return t;
}

}  // namespace

Pb FloatTensor(const std::string& name, const std::vector<int64_t>& dims, const std::vector<float>& values) {
  return Tensor(name, dims, 1, values.data(), values.size() * 4);
}

Pb Int64Tensor(const std::string& name, const std::vector<int64_t>& values) {
  return Tensor(name, {static_cast<int64_t>(values.size())}, 7, values.data(), values.size() * 8);
}

// AttributeProto: name 1, i 3, ints 8, type 20 (INT = 2, INTS = 7).
Pb IntAttribute(const std::string& name, int64_t v) {
  Pb a;
  a.Bytes(1, name);
  a.Int(3, v);
  a.Int(20, 2);
  return a;
}

// AttributeProto s 4, type STRING = 3.
Pb StringAttribute(const std::string& name, const std::string& v) {
  Pb a;
  a.Bytes(1, name);
  a.Bytes(4, v);
  a.Int(20, 3);
  return a;
}

Pb IntsAttribute(const std::string& name, const std::vector<int64_t>& v) {
  Pb a;
  a.Bytes(1, name);
  for (int64_t x : v) a.Int(8, x);
  a.Int(20, 7);
  return a;
}

// NodeProto: input 1, output 2, name 3, op_type 4, attribute 5.
Pb Node(const std::string& op, const std::vector<std::string>& inputs, const std::string& output,
        const std::vector<Pb>& attributes) {
  Pb n;
  for (const std::string& s : inputs) n.Bytes(1, s);
  n.Bytes(2, output);
  n.Bytes(3, output + "_node");
  n.Bytes(4, op);
  for (const Pb& a : attributes) n.Msg(5, a);
  return n;
}

// ValueInfoProto: name 1, type 2 -> TypeProto.tensor_type 1 -> elem_type 1, shape 2 -> dim 1 -> dim_value 1.
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

// ModelProto: ir_version 1, producer_name 2, graph 7, opset_import 8 (domain 1, version 2).
void WriteModel(const Pb& graph, int opset, const std::string& producer, const std::string& path) {
  Pb model;
  model.Int(1, 7);
  model.Bytes(2, producer);
  model.Msg(7, graph);
  Pb op;
  op.Bytes(1, "");
  op.Int(2, opset);
  model.Msg(8, op);
  std::ofstream out(path, std::ios::binary);
  out.write(model.b.data(), static_cast<std::streamsize>(model.b.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace dynref::test::onnx
