#include "tiny_layout_onnx.h"

#include <stdexcept>

#include "onnx_protobuf.h"

namespace dynref::test {

using namespace onnx;

void WriteTinyLayoutOnnx(const std::string& path, int height, int width, const std::vector<LayoutOutput>& outputs) {
  const int64_t input_total = 3 * int64_t(height) * width;
  Pb g;
  g.Msg(1, Node("Reshape", {"images", "shape_flat"}, "flat"));
  g.Msg(5, Int64Tensor("shape_flat", {1, input_total}));
  g.Msg(5, Int64Tensor("axis1", {1}));
  int64_t pos = 0;
  for (size_t o = 0; o < outputs.size(); ++o) {
    const LayoutOutput& out = outputs[o];
    const std::string p = "o" + std::to_string(o) + "_";
    std::vector<int64_t> pre = out.shape;
    int64_t total = 1;
    for (size_t i = 0; i < pre.size(); ++i) {
      if (out.upsample > 1 && i + 2 >= pre.size()) {
        if (pre[i] % out.upsample) throw std::invalid_argument(out.name + ": shape not divisible by upsample");
        pre[i] /= out.upsample;
      }
      total *= pre[i];
    }
    std::vector<std::string> parts;
    int64_t covered = 0;
    for (size_t s = 0; s < out.segments.size(); ++s) {
      const LayoutSegment& seg = out.segments[s];
      const std::string q = p + "s" + std::to_string(s) + "_";
      g.Msg(5, Int64Tensor(q + "begin", {pos}));
      g.Msg(5, Int64Tensor(q + "end", {pos + seg.length}));
      g.Msg(1, Node("Slice", {"flat", q + "begin", q + "end", "axis1"}, q + "raw"));
      std::string cur = q + "raw";
      if (seg.scale != 1) {
        g.Msg(5, FloatTensor(q + "scale", {1}, {seg.scale}));
        g.Msg(1, Node("Mul", {cur, q + "scale"}, q + "scaled"));
        cur = q + "scaled";
      }
      if (seg.offset != 0) {
        g.Msg(5, FloatTensor(q + "offset", {1}, {seg.offset}));
        g.Msg(1, Node("Add", {cur, q + "offset"}, q + "shifted"));
        cur = q + "shifted";
      }
      parts.push_back(cur);
      pos += seg.length;
      covered += seg.length;
    }
    if (covered != total) throw std::invalid_argument(out.name + ": segments cover " + std::to_string(covered) + " of " + std::to_string(total));
    if (pos > input_total) throw std::invalid_argument(out.name + ": the input has too few values");
    std::string joined = parts.front();
    if (parts.size() > 1) {
      joined = p + "joined";
      g.Msg(1, Node("Concat", parts, joined, {IntAttribute("axis", 1)}));
    }
    const std::string shaped = out.upsample > 1 ? p + "small" : out.name;
    g.Msg(5, Int64Tensor(p + "shape", pre));
    g.Msg(1, Node("Reshape", {joined, p + "shape"}, shaped));
    if (out.upsample > 1) {
      if (out.shape.size() != 4) throw std::invalid_argument(out.name + ": upsample needs a 4-D output");
      const float u = float(out.upsample);
      g.Msg(5, FloatTensor(p + "scales", {4}, {1, 1, u, u}));
      g.Msg(1, Node("Resize", {shaped, "", p + "scales"}, out.name, {StringAttribute("mode", "nearest")}));
    }
  }
  g.Bytes(2, "tiny_layout");
  g.Msg(11, ValueInfo("images", {1, 3, height, width}));
  for (const LayoutOutput& out : outputs) g.Msg(12, ValueInfo(out.name, out.shape));
  WriteModel(g, 12, "dynref-test", path);
}

void SetFlatPixel(cv::Mat& bgr, int64_t k, int pixel) {
  const int64_t plane = int64_t(bgr.rows) * bgr.cols;
  const int c = int(k / plane);
  const int64_t r = k % plane;
  bgr.at<cv::Vec3b>(int(r / bgr.cols), int(r % bgr.cols))[2 - c] = uchar(pixel);
}

}  // namespace dynref::test
