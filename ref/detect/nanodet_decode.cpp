#include "detect/nanodet_decode.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dynref::detect {

cv::Mat AsRows(const cv::Mat& blob) {
  if (blob.type() != CV_32F) throw std::invalid_argument("network output is not CV_32F");
  if (blob.dims == 2) return blob;
  if (blob.dims == 3 && blob.size[0] == 1) return cv::Mat(blob.size[1], blob.size[2], CV_32F, const_cast<uchar*>(blob.data));
  throw std::invalid_argument("network output must be [1, N, C], got " + std::to_string(blob.dims) + " dims");
}

double DistributionExpectation(const float* logits, int bins) {
  double max_logit = logits[0];
  for (int k = 1; k < bins; ++k) max_logit = std::max(max_logit, double(logits[k]));
  double sum = 0, weighted = 0;
  for (int k = 0; k < bins; ++k) {
    const double e = std::exp(double(logits[k]) - max_logit);
    sum += e;
    weighted += e * k;
  }
  return weighted / sum;
}

std::vector<Candidate> DecodeNanodet(const std::vector<NanodetLevel>& levels,
                                     const NanodetDecodeOptions& options) {
  const int bins = options.reg_max + 1;
  const double sx = double(options.image_width) / options.input_size;
  const double sy = double(options.image_height) / options.input_size;
  std::vector<Candidate> out;
  int anchor_base = 0;
  for (const NanodetLevel& level : levels) {
    const int n = options.input_size / level.stride;  // cells per row
    const cv::Mat scores = AsRows(level.scores);
    const cv::Mat boxes = AsRows(level.boxes);
    if (scores.rows != n * n || boxes.rows != n * n || boxes.cols != 4 * bins)
      throw std::invalid_argument("NanoDet level stride " + std::to_string(level.stride) + ": expected " +
                                  std::to_string(n * n) + " cells and " + std::to_string(4 * bins) +
                                  " box bins, got scores " + std::to_string(scores.rows) + "x" +
                                  std::to_string(scores.cols) + ", boxes " + std::to_string(boxes.rows) +
                                  "x" + std::to_string(boxes.cols));
    for (int i = 0; i < n * n; ++i) {
      const float* s = scores.ptr<float>(i);
      int best = 0;
      for (int c = 1; c < scores.cols; ++c)
        if (s[c] > s[best]) best = c;  // first maximum wins ties
      if (!(s[best] > options.score_threshold)) continue;
      // Cell centre ((i mod n) + offset, (i div n) + offset) * stride, in 416-pixel units.
      const double cx = (double(i % n) + options.cell_offset) * level.stride;
      const double cy = (double(i / n) + options.cell_offset) * level.stride;
      const float* b = boxes.ptr<float>(i);
      const double l = level.stride * DistributionExpectation(b, bins);
      const double t = level.stride * DistributionExpectation(b + bins, bins);
      const double r = level.stride * DistributionExpectation(b + 2 * bins, bins);
      const double d = level.stride * DistributionExpectation(b + 3 * bins, bins);
      Candidate c;
      c.class_id = best;
      c.score = s[best];
      c.x_min = (cx - l) * sx;
      c.y_min = (cy - t) * sy;
      c.x_max = (cx + r) * sx;
      c.y_max = (cy + d) * sy;
      c.anchor = anchor_base + i;
      ClipBox(c, options.image_width, options.image_height);
      out.push_back(c);
    }
    anchor_base += n * n;
  }
  return out;
}

}  // namespace dynref::detect
