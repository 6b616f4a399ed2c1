// SuperPoint-style ONNX extractor; see onnx_extractor.h.
#include "features/onnx_extractor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/error.h"

namespace dynref::features {
namespace {

constexpr int kCell = 8;

int RoundUp(int v, int m) { return (v + m - 1) / m * m; }

// Value of channel c of a 1 x C x H x W blob at (y, x).
inline float At(const cv::Mat& blob, int c, int y, int x) {
  return blob.ptr<float>(0, c)[static_cast<size_t>(y) * blob.size[3] + x];
}

}  // namespace

cv::Mat DecodeScoreMap(const cv::Mat& out, int height, int width) {
  if (out.dims != 4 || out.size[0] != 1 || out.type() != CV_32F)
    throw std::invalid_argument("score output must be a 1 x C x H x W float blob");
  const int C = out.size[1], h = out.size[2], w = out.size[3];
  cv::Mat scores(height, width, CV_32F, cv::Scalar(0));
  // The map covers the image as the network saw it (padded to 8 x 8 cells), exactly: a larger map
  // placed keypoints at the wrong pixels (issue 37: a score map 2x the resolution ran).
  const int ph = (height + kCell - 1) / kCell * kCell, pw = (width + kCell - 1) / kCell * kCell;
  const std::string got = std::to_string(C) + " x " + std::to_string(h) + " x " + std::to_string(w);
  if (C == 1) {
    if (!((h == height || h == ph) && (w == width || w == pw)))
      throw std::invalid_argument("1-channel score output must be " + std::to_string(ph) + " x " + std::to_string(pw) +
                                  " (the padded input), got " + got);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) scores.at<float>(y, x) = At(out, 0, y, x);
    return scores;
  }
  if (C != kCell * kCell + 1 || h * kCell != ph || w * kCell != pw)
    throw std::invalid_argument("score output must be 65 x " + std::to_string(ph / kCell) + " x " +
                                std::to_string(pw / kCell) + " (8 x 8 cells of the padded input, SuperPoint) or 1 x " +
                                std::to_string(ph) + " x " + std::to_string(pw) + ", got " + got);
  std::vector<double> e(static_cast<size_t>(C));
  for (int cy = 0; cy < h; ++cy)
    for (int cx = 0; cx < w; ++cx) {
      double mx = -INFINITY;
      for (int c = 0; c < C; ++c) mx = std::max(mx, static_cast<double>(At(out, c, cy, cx)));
      double sum = 0;
      for (int c = 0; c < C; ++c) sum += (e[static_cast<size_t>(c)] = std::exp(At(out, c, cy, cx) - mx));
      for (int c = 0; c < C - 1; ++c) {
        const int y = cy * kCell + c / kCell, x = cx * kCell + c % kCell;
        if (y < height && x < width) scores.at<float>(y, x) = static_cast<float>(e[static_cast<size_t>(c)] / sum);
      }
    }
  return scores;
}

std::vector<cv::KeyPoint> SelectKeypoints(const cv::Mat& scores, double threshold, int nms_radius, int border,
                                          int n_features) {
  struct Cand {
    float s;
    int y, x;
  };
  std::vector<Cand> cand;
  for (int y = border; y < scores.rows - border; ++y)
    for (int x = border; x < scores.cols - border; ++x)
      if (scores.at<float>(y, x) > threshold) cand.push_back({scores.at<float>(y, x), y, x});
  std::sort(cand.begin(), cand.end(), [](const Cand& a, const Cand& b) {
    if (a.s != b.s) return a.s > b.s;
    return a.y != b.y ? a.y < b.y : a.x < b.x;
  });
  cv::Mat taken(scores.size(), CV_8U, cv::Scalar(0));  // pixels suppressed by an accepted keypoint
  std::vector<cv::KeyPoint> keys;
  for (const Cand& c : cand) {
    if (static_cast<int>(keys.size()) >= n_features) break;
    if (taken.at<uint8_t>(c.y, c.x)) continue;
    cv::KeyPoint kp(static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(2 * nms_radius + 1), 0.f, c.s, 0);
    keys.push_back(kp);
    const int y0 = std::max(0, c.y - nms_radius), y1 = std::min(scores.rows - 1, c.y + nms_radius);
    const int x0 = std::max(0, c.x - nms_radius), x1 = std::min(scores.cols - 1, c.x + nms_radius);
    taken(cv::Range(y0, y1 + 1), cv::Range(x0, x1 + 1)).setTo(1);
  }
  return keys;
}

cv::Mat SampleDescriptors(const cv::Mat& out, const std::vector<cv::KeyPoint>& keys, int height, int width,
                          bool binary) {
  if (out.dims != 4 || out.size[0] != 1 || out.type() != CV_32F)
    throw std::invalid_argument("descriptor output must be a 1 x D x H x W float blob");
  const int D = out.size[1], h = out.size[2], w = out.size[3];
  if (binary && D % 8 != 0) throw std::invalid_argument("binary descriptors need D divisible by 8, got " + std::to_string(D));
  cv::Mat rows(static_cast<int>(keys.size()), D, CV_32F);
  for (size_t k = 0; k < keys.size(); ++k) {
    const double xd = std::clamp((keys[k].pt.x + 0.5) * w / width - 0.5, 0.0, w - 1.0);
    const double yd = std::clamp((keys[k].pt.y + 0.5) * h / height - 0.5, 0.0, h - 1.0);
    const int x0 = static_cast<int>(xd), y0 = static_cast<int>(yd);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double ax = xd - x0, ay = yd - y0;
    float* r = rows.ptr<float>(static_cast<int>(k));
    for (int c = 0; c < D; ++c) {
      const double top = (1 - ax) * At(out, c, y0, x0) + ax * At(out, c, y0, x1);
      const double bottom = (1 - ax) * At(out, c, y1, x0) + ax * At(out, c, y1, x1);
      r[c] = static_cast<float>((1 - ay) * top + ay * bottom);
    }
  }
  if (!binary) {
    NormaliseRows(&rows);
    return rows;
  }
  cv::Mat bits(rows.rows, D / 8, CV_8U, cv::Scalar(0));
  for (int k = 0; k < rows.rows; ++k)
    for (int c = 0; c < D; ++c)
      if (rows.at<float>(k, c) > 0) bits.at<uint8_t>(k, c / 8) |= static_cast<uint8_t>(1u << (c % 8));
  return bits;
}

OnnxExtractor::OnnxExtractor(const OnnxOptions& options) : options_(options) {
  if (options_.model.empty()) throw InputError("backbone.onnx_model", "features: onnx needs a model file");
  try {
    net_ = cv::dnn::readNetFromONNX(options_.model);
  } catch (const cv::Exception& e) {
    throw InputError(options_.model, "cannot load the ONNX model: " + std::string(e.what()));
  }
  if (net_.empty()) throw InputError(options_.model, "cannot load the ONNX model");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
}

void OnnxExtractor::Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors) {
  const int H = RoundUp(grey.rows, kCell), W = RoundUp(grey.cols, kCell);
  cv::Mat padded(H, W, CV_8U, cv::Scalar(0));
  grey.copyTo(padded(cv::Rect(0, 0, grey.cols, grey.rows)));
  const cv::Mat blob = cv::dnn::blobFromImage(padded, 1.0 / 255.0);
  std::vector<cv::Mat> outs;
  try {
    net_.setInput(blob);
    net_.forward(outs, std::vector<std::string>{options_.score_output, options_.descriptor_output});
  } catch (const cv::Exception& e) {
    throw InputError(options_.model, "forward pass failed (outputs '" + options_.score_output + "', '" +
                                         options_.descriptor_output + "'): " + e.what());
  }
  try {
    const cv::Mat scores = DecodeScoreMap(outs[0], grey.rows, grey.cols);
    *keys = SelectKeypoints(scores, options_.score_threshold, options_.nms_radius, options_.border, options_.n_features);
    // The descriptor map covers the padded image.
    *descriptors = SampleDescriptors(outs[1], *keys, H, W, options_.binary);
  } catch (const std::invalid_argument& e) {
    throw InputError(options_.model, e.what());
  }
  descriptor_dim_ = descriptors->cols;
}

DescriptorProfile OnnxExtractor::profile() const {
  DescriptorProfile p;
  p.extractor = "onnx";
  p.oriented = false;
  p.n_levels = 1;
  if (options_.binary) {
    // ORB-SLAM2's bit gates scaled to the string length.
    const float bits = static_cast<float>(std::max(1, descriptor_dim_) * 8);
    p.type = CV_8U;
    p.cols = std::max(1, descriptor_dim_);
    p.worst = bits;
    p.th_low = kThLow * bits / 256, p.th_high = kThHigh * bits / 256, p.th_reloc = 64 * bits / 256;
    return p;
  }
  // Spec 004 (c): the Hamming equivalents 4 * bits / 256 of ORB-SLAM2's gates on unit rows.
  p.type = CV_32F;
  p.cols = std::max(1, descriptor_dim_);
  p.worst = 4;
  p.th_low = 4.f * kThLow / 256, p.th_high = 4.f * kThHigh / 256, p.th_reloc = 4.f * 64 / 256;
  return p;
}

}  // namespace dynref::features
