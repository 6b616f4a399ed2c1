#include "detect/yolo_decode.h"

#include <opencv2/imgproc.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dynref::detect {

Letterbox ComputeLetterbox(int image_width, int image_height, int input_size) {
  if (image_width <= 0 || image_height <= 0 || input_size <= 0)
    throw std::invalid_argument("letterbox: empty image or input size");
  Letterbox lb;
  lb.input_size = input_size;
  lb.image_width = image_width;
  lb.image_height = image_height;
  lb.scale = std::min(double(input_size) / image_width, double(input_size) / image_height);
  lb.scaled_width = std::max(1, int(std::lround(image_width * lb.scale)));
  lb.scaled_height = std::max(1, int(std::lround(image_height * lb.scale)));
  lb.pad_left = (input_size - lb.scaled_width) / 2;
  lb.pad_top = (input_size - lb.scaled_height) / 2;
  return lb;
}

cv::Mat ApplyLetterbox(const cv::Mat& bgr, const Letterbox& lb) {
  cv::Mat out(lb.input_size, lb.input_size, CV_8UC3, cv::Scalar(114, 114, 114));
  cv::Mat scaled;
  cv::resize(bgr, scaled, cv::Size(lb.scaled_width, lb.scaled_height), 0, 0, cv::INTER_LINEAR);
  scaled.copyTo(out(cv::Rect(lb.pad_left, lb.pad_top, lb.scaled_width, lb.scaled_height)));
  return out;
}

int YoloAnchorCount(int input_size) {
  int total = 0;
  for (int stride : {8, 16, 32}) total += (input_size / stride) * (input_size / stride);
  return total;
}

YoloPredictions ArrangeYoloPredictions(const cv::Mat& output, int input_size, int num_mask_coeffs) {
  if (output.type() != CV_32F) throw std::invalid_argument("YOLO output is not float32");
  int d1 = 0, d2 = 0;
  if (output.dims == 3 && output.size[0] == 1) {
    d1 = output.size[1];
    d2 = output.size[2];
  } else if (output.dims == 2) {
    d1 = output.rows;
    d2 = output.cols;
  } else {
    throw std::invalid_argument("YOLO output must be [1, C, A] or [1, A, C]");
  }
  const int anchors = YoloAnchorCount(input_size);
  cv::Mat as2d(d1, d2, CV_32F, const_cast<uchar*>(output.data));
  YoloPredictions p;
  if (d2 == anchors) {
    p.channels_by_anchor = as2d.clone();
  } else if (d1 == anchors) {
    p.channels_by_anchor = as2d.t();
  } else {
    throw std::invalid_argument("YOLO output " + std::to_string(d1) + "x" + std::to_string(d2) +
                                " has no dimension of " + std::to_string(anchors) + " anchors for input size " +
                                std::to_string(input_size));
  }
  p.num_mask_coeffs = num_mask_coeffs;
  p.num_classes = p.channels_by_anchor.rows - 4 - num_mask_coeffs;
  if (p.num_classes < 1)
    throw std::invalid_argument("YOLO output has " + std::to_string(p.channels_by_anchor.rows) +
                                " channels, too few for 4 box + classes + " + std::to_string(num_mask_coeffs) +
                                " mask coefficients");
  return p;
}

std::vector<Candidate> DecodeYoloBoxes(const YoloPredictions& pred, const Letterbox& lb,
                                       double score_threshold) {
  const cv::Mat& m = pred.channels_by_anchor;
  std::vector<Candidate> out;
  for (int a = 0; a < m.cols; ++a) {
    int best = 0;
    float best_score = m.at<float>(4, a);
    for (int c = 1; c < pred.num_classes; ++c) {
      const float s = m.at<float>(4 + c, a);
      if (s > best_score) {
        best_score = s;
        best = c;
      }
    }
    if (!(best_score > score_threshold)) continue;
    const double cx = m.at<float>(0, a), cy = m.at<float>(1, a);
    const double w = m.at<float>(2, a), h = m.at<float>(3, a);
    Candidate c;
    c.class_id = best;
    c.score = best_score;
    c.x_min = (cx - 0.5 * w - lb.pad_left) / lb.scale;
    c.y_min = (cy - 0.5 * h - lb.pad_top) / lb.scale;
    c.x_max = (cx + 0.5 * w - lb.pad_left) / lb.scale;
    c.y_max = (cy + 0.5 * h - lb.pad_top) / lb.scale;
    c.anchor = a;
    ClipBox(c, lb.image_width, lb.image_height);
    out.push_back(c);
  }
  return out;
}

cv::Mat DecodeYoloMask(const YoloPredictions& pred, const cv::Mat& protos, const Candidate& c,
                       const Letterbox& lb) {
  const int nm = pred.num_mask_coeffs;
  int ph = 0, pw = 0;
  if (protos.dims == 4 && protos.size[0] == 1 && protos.size[1] == nm) {
    ph = protos.size[2];
    pw = protos.size[3];
  } else if (protos.dims == 3 && protos.size[0] == nm) {
    ph = protos.size[1];
    pw = protos.size[2];
  } else {
    throw std::invalid_argument("YOLO prototypes must be [1, " + std::to_string(nm) + ", h, w]");
  }
  if (protos.type() != CV_32F) throw std::invalid_argument("YOLO prototypes are not float32");
  const cv::Mat proto_rows(nm, ph * pw, CV_32F, const_cast<uchar*>(protos.data));
  cv::Mat coeffs(1, nm, CV_32F);
  for (int k = 0; k < nm; ++k) coeffs.at<float>(0, k) = pred.channels_by_anchor.at<float>(4 + pred.num_classes + k, c.anchor);
  // Linear combination of prototypes (YOLACT, Bolya et al. 2019, Eq. (1)), in double for a
  // summation order that does not depend on BLAS.
  cv::Mat prob(ph, pw, CV_32F);
  for (int i = 0; i < ph * pw; ++i) {
    double v = 0;
    for (int k = 0; k < nm; ++k) v += double(coeffs.at<float>(0, k)) * proto_rows.at<float>(k, i);
    prob.at<float>(i / pw, i % pw) = float(1.0 / (1.0 + std::exp(-v)));
  }
  cv::Mat in_size;
  cv::resize(prob, in_size, cv::Size(lb.input_size, lb.input_size), 0, 0, cv::INTER_LINEAR);
  cv::Mat unpadded = in_size(cv::Rect(lb.pad_left, lb.pad_top, lb.scaled_width, lb.scaled_height));
  cv::Mat img_prob;
  cv::resize(unpadded, img_prob, cv::Size(lb.image_width, lb.image_height), 0, 0, cv::INTER_LINEAR);
  cv::Mat mask = img_prob > 0.5f;
  // Crop to the box (pixels whose centre lies inside it).
  cv::Mat crop = cv::Mat::zeros(mask.size(), CV_8U);
  const int x0 = std::max(0, int(std::ceil(c.x_min - 0.5))), y0 = std::max(0, int(std::ceil(c.y_min - 0.5)));
  const int x1 = std::min(lb.image_width, int(std::ceil(c.x_max - 0.5)));
  const int y1 = std::min(lb.image_height, int(std::ceil(c.y_max - 0.5)));
  if (x1 > x0 && y1 > y0) crop(cv::Rect(x0, y0, x1 - x0, y1 - y0)).setTo(255);
  return mask & crop;
}

}  // namespace dynref::detect
