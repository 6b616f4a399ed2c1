// Hand-encoded ONNX protobuf for the tests' tiny models (no ONNX library on the machine): the
// wire format (varints, length-delimited fields) and the few onnx.proto messages the tiny
// detector (tests/detect/tiny_onnx.h) and the tiny SuperPoint (tests/tiny_onnx_model.h) need.
// Field numbers are onnx.proto's.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dynref::test::onnx {

// One protobuf message being written (wire types 0 = varint, 2 = length-delimited).
struct Pb {
  std::string b;
  void Varint(uint64_t v);
  Pb& Int(int field, int64_t v);
  Pb& Bytes(int field, const std::string& s);
  Pb& Msg(int field, const Pb& m) { return Bytes(field, m.b); }
};

// TensorProto (raw little-endian data): FLOAT with dims, INT64 as a 1-D tensor of the values.
Pb FloatTensor(const std::string& name, const std::vector<int64_t>& dims, const std::vector<float>& values);
Pb Int64Tensor(const std::string& name, const std::vector<int64_t>& values);
// AttributeProto: INT and INTS.
Pb IntAttribute(const std::string& name, int64_t v);
Pb IntsAttribute(const std::string& name, const std::vector<int64_t>& v);
Pb StringAttribute(const std::string& name, const std::string& v);
// NodeProto named out + "_node".
Pb Node(const std::string& op, const std::vector<std::string>& inputs, const std::string& output,
        const std::vector<Pb>& attributes = {});
// ValueInfoProto of a FLOAT tensor of a fixed shape.
Pb ValueInfo(const std::string& name, const std::vector<int64_t>& shape);
// ModelProto (ir_version 7, default-domain opset) around the graph, written to path
// (std::runtime_error when it cannot be written).
void WriteModel(const Pb& graph, int opset, const std::string& producer, const std::string& path);

}  // namespace dynref::test::onnx
