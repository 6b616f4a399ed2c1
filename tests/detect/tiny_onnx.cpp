#include "tiny_onnx.h"

#include <cstdint>
#include <vector>

#include "onnx_protobuf.h"

namespace dynref::test {

using namespace onnx;

void WriteTinyYoloSegOnnx(const std::string& path, int s) {
  const int64_t anchors = (s / 8) * (s / 8) + (s / 16) * (s / 16) + (s / 32) * (s / 32);
  const int64_t channels = 6, box_end = 4 * anchors, pred_end = channels * anchors;
  const int64_t proto_side = s / 4, proto_end = pred_end + proto_side * proto_side;
  Pb g;
  g.Msg(1, Node("Reshape", {"images", "shape_flat"}, "flat"));
  g.Msg(1, Node("Slice", {"flat", "zero", "box_end", "axis1"}, "box_raw"));
  g.Msg(1, Node("Mul", {"box_raw", "box_scale"}, "box"));
  g.Msg(1, Node("Slice", {"flat", "box_end", "pred_end", "axis1"}, "rest"));
  g.Msg(1, Node("Concat", {"box", "rest"}, "pred_flat", {IntAttribute("axis", 1)}));
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
  g.Msg(5, FloatTensor("box_scale", {1}, {float(kTinyBoxScale)}));
  g.Msg(11, ValueInfo("images", {1, 3, s, s}));
  g.Msg(12, ValueInfo("output0", {1, channels, anchors}));
  g.Msg(12, ValueInfo("output1", {1, 1, proto_side, proto_side}));
  WriteModel(g, 12, "dynref-test", path);
}

}  // namespace dynref::test
