#include "detect/yolact_decode.h"
#include "detect/mat_shape.h"

#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynref::detect {
namespace {

// [1, P, n] or [P, n] -> P x n view (CV_32F).
cv::Mat Rows(const cv::Mat& m, const std::string& what) {
  if (m.type() != CV_32F) throw std::invalid_argument("YOLACT " + what + " output is not float32");
  if (m.dims == 3 && m.size[0] == 1) return cv::Mat(m.size[1], m.size[2], CV_32F, const_cast<uchar*>(m.ptr<uchar>()));
  if (m.dims == 2) return m;
  throw std::invalid_argument("YOLACT " + what + " output is " + MatShapeText(m) + ", expected [1, P, n]");
}

}  // namespace

YolactLayout YolactLayoutForInput(int input_size) {
  if (input_size < 32) throw std::invalid_argument("YOLACT input size must be >= 32");
  YolactLayout l;
  l.input_size = input_size;
  int c = (input_size + 7) / 8;
  for (int& s : l.conv_sizes) {
    s = c;
    c = (c + 1) / 2;
  }
  return l;
}

cv::Mat YolactPriors(const YolactLayout& l) {
  std::vector<float> data;
  for (size_t level = 0; level < l.conv_sizes.size(); ++level) {
    const int n = l.conv_sizes[level];
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (double ar : l.aspect_ratios) {
          const double w = l.scales[level] * std::sqrt(ar) / l.input_size;  // h = w (use_square_anchors)
          for (double v : {(i + 0.5) / n, (j + 0.5) / n, w, w}) data.push_back(float(v));
        }
  }
  return cv::Mat(int(data.size() / 4), 4, CV_32F, data.data()).clone();
}

YolactOutputs ArrangeYolactOutputs(const std::vector<cv::Mat>& outs, const std::vector<std::string>& names,
                                   int prior_count) {
  if (outs.size() != 4)
    throw std::invalid_argument("YOLACT export has " + std::to_string(outs.size()) +
                                " outputs, expected 4 (loc, conf, mask, proto)");
  int loc = -1, conf = -1, mask = -1, proto = -1;
  for (size_t i = 0; i < names.size() && names.size() == 4; ++i) {
    if (names[i] == "loc") loc = int(i);
    if (names[i] == "conf") conf = int(i);
    if (names[i] == "mask") mask = int(i);
    if (names[i] == "proto") proto = int(i);
  }
  if (loc < 0 || conf < 0 || mask < 0 || proto < 0) {  // by shape
    loc = conf = mask = proto = -1;
    for (int i = 0; i < 4; ++i)
      if (outs[i].dims == 4) proto = i;
    if (proto < 0) throw std::invalid_argument("YOLACT export has no 4-D prototype output [1, h, w, k]");
    const int k = outs[proto].size[3];
    for (int i = 0; i < 4; ++i) {
      if (i == proto) continue;
      const int cols = outs[i].size[outs[i].dims - 1];
      (cols == 4 && loc < 0 ? loc : cols == k && mask < 0 ? mask : conf) = i;
    }
  }
  const cv::Mat& p = outs[proto];
  if (p.dims != 4 || p.size[0] != 1 || p.type() != CV_32F)
    throw std::invalid_argument("YOLACT proto output is " + MatShapeText(p) + ", expected float [1, h, w, k]");
  YolactOutputs o;
  o.loc = Rows(outs[loc], "loc");
  o.conf = Rows(outs[conf], "conf");
  o.coeffs = Rows(outs[mask], "mask");
  o.proto_h = p.size[1];
  o.proto_w = p.size[2];
  o.proto = cv::Mat(o.proto_h * o.proto_w, p.size[3], CV_32F, const_cast<uchar*>(p.ptr<uchar>()));
  if (o.loc.cols != 4) throw std::invalid_argument("YOLACT loc has " + std::to_string(o.loc.cols) + " columns, expected 4");
  if (o.coeffs.cols != o.proto.cols)
    throw std::invalid_argument("YOLACT mask has " + std::to_string(o.coeffs.cols) + " coefficients, proto " +
                                std::to_string(o.proto.cols) + " channels");
  if (o.conf.cols < 2) throw std::invalid_argument("YOLACT conf needs background + at least one class");
  for (const cv::Mat* m : {&o.loc, &o.conf, &o.coeffs})
    if (m->rows != prior_count)
      throw std::invalid_argument("YOLACT outputs have " + std::to_string(m->rows) + " priors, the input size gives " +
                                  std::to_string(prior_count) + " (export size and --input-size differ?)");
  return o;
}

std::vector<Candidate> DecodeYolactBoxes(const YolactOutputs& out, const cv::Mat& priors, cv::Size image,
                                         double threshold, const YolactLayout& layout) {
  std::vector<Candidate> cands;
  for (int p = 0; p < out.conf.rows; ++p) {
    int best = 1;
    for (int c = 2; c < out.conf.cols; ++c)
      if (out.conf.at<float>(p, c) > out.conf.at<float>(p, best)) best = c;
    const double score = out.conf.at<float>(p, best);
    if (!(score > threshold)) continue;
    // layers/box_utils.py decode (use_yolo_regressors False).
    const double pcx = priors.at<float>(p, 0), pcy = priors.at<float>(p, 1);
    const double pw = priors.at<float>(p, 2), ph = priors.at<float>(p, 3);
    const double cx = pcx + out.loc.at<float>(p, 0) * layout.variance_center * pw;
    const double cy = pcy + out.loc.at<float>(p, 1) * layout.variance_center * ph;
    const double w = pw * std::exp(out.loc.at<float>(p, 2) * layout.variance_size);
    const double h = ph * std::exp(out.loc.at<float>(p, 3) * layout.variance_size);
    Candidate c;
    c.class_id = best - 1;
    c.score = score;
    c.x_min = (cx - 0.5 * w) * image.width;
    c.y_min = (cy - 0.5 * h) * image.height;
    c.x_max = (cx + 0.5 * w) * image.width;
    c.y_max = (cy + 0.5 * h) * image.height;
    c.anchor = p;
    ClipBox(c, image.width, image.height);
    cands.push_back(c);
  }
  return cands;
}

cv::Mat DecodeYolactMask(const YolactOutputs& out, const Candidate& c, cv::Size image) {
  const int ph = out.proto_h, pw = out.proto_w, k = out.proto.cols;
  // Box at prototype resolution, sanitised with padding 1 (layers/box_utils.py crop).
  const double x1 = std::max(0.0, c.x_min / image.width * pw - 1), x2 = std::min(double(pw), c.x_max / image.width * pw + 1);
  const double y1 = std::max(0.0, c.y_min / image.height * ph - 1), y2 = std::min(double(ph), c.y_max / image.height * ph + 1);
  cv::Mat prob(ph, pw, CV_32F);
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      double v = 0;  // in double: a summation order that does not depend on BLAS
      for (int j = 0; j < k; ++j) v += double(out.proto.at<float>(y * pw + x, j)) * out.coeffs.at<float>(c.anchor, j);
      const bool inside = x >= x1 && x < x2 && y >= y1 && y < y2;
      prob.at<float>(y, x) = inside ? float(1.0 / (1.0 + std::exp(-v))) : 0.f;
    }
  cv::Mat img_prob;
  cv::resize(prob, img_prob, image, 0, 0, cv::INTER_LINEAR);
  return img_prob > 0.5f;
}

cv::Mat YolactBlob(const cv::Mat& bgr, int input_size) {
  cv::Mat resized, f;
  cv::resize(bgr, resized, cv::Size(input_size, input_size), 0, 0, cv::INTER_LINEAR);
  resized.convertTo(f, CV_32FC3);
  const double mean[3] = {103.94, 116.78, 123.68}, stdev[3] = {57.38, 57.12, 58.40};  // B, G, R
  const int sz[4] = {1, 3, input_size, input_size};
  cv::Mat blob(4, sz, CV_32F);
  for (int c = 0; c < 3; ++c) {  // blob channel c = R, G, B
    const int b = 2 - c;
    cv::Mat plane(input_size, input_size, CV_32F, blob.ptr<float>(0, c));
    for (int y = 0; y < input_size; ++y)
      for (int x = 0; x < input_size; ++x)
        plane.at<float>(y, x) = float((f.at<cv::Vec3f>(y, x)[b] - mean[b]) / stdev[b]);
  }
  return blob;
}

}  // namespace dynref::detect
