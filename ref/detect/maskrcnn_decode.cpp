#include "detect/maskrcnn_decode.h"
#include "detect/mat_shape.h"

#include <cmath>
#include <stdexcept>

namespace dynref::detect {
namespace {

// [N, 1] / [1, N] / [N]: N values, as a column (CV_32F).
cv::Mat Column(const cv::Mat& m, int n, const std::string& what) {
  if (int(m.total()) != n)
    throw std::invalid_argument(what + " is " + MatShapeText(m) + ", expected [" + std::to_string(n) + "] (one per box)");
  if (n == 0) return cv::Mat(0, 1, CV_32F);
  const cv::Mat c = m.isContinuous() ? m : m.clone();
  cv::Mat f;
  cv::Mat(n, 1, CV_MAKETYPE(c.depth(), 1), c.data).convertTo(f, CV_32F);
  return f;
}

}  // namespace

int Coco91ToCoco80(int category_id) {
  // The 80 used ids of the 91-id scheme, in order (COCO 2017 annotations / torchvision's
  // COCO_V1_CATEGORIES without "__background__" and "N/A").
  static const int kUsed[80] = {1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 13, 14, 15, 16, 17, 18, 19, 20, 21,
                                22, 23, 24, 25, 27, 28, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44,
                                46, 47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63, 64, 65,
                                67, 70, 72, 73, 74, 75, 76, 77, 78, 79, 80, 81, 82, 84, 85, 86, 87, 88, 89, 90};
  for (int i = 0; i < 80; ++i)
    if (kUsed[i] == category_id) return i;
  return -1;
}

MaskRcnnOutputs ArrangeMaskRcnnOutputs(const std::vector<cv::Mat>& outs, const std::vector<std::string>& names) {
  if (outs.size() != 3 && outs.size() != 4)
    throw std::invalid_argument("Mask R-CNN export has " + std::to_string(outs.size()) +
                                " outputs, expected 4 (boxes, labels, scores, masks) or 3 (no masks)");
  const char* const kNames[4] = {"boxes", "labels", "scores", "masks"};
  std::vector<int> at(outs.size(), -1);
  bool by_name = names.size() == outs.size();
  for (size_t k = 0; k < outs.size() && by_name; ++k) {
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == kNames[k]) at[k] = int(i);
    by_name = at[k] >= 0;
  }
  for (size_t k = 0; k < outs.size(); ++k)
    if (!by_name) at[k] = int(k);  // torchvision's order
  const cv::Mat& boxes = outs[at[0]];
  if (boxes.type() != CV_32F) throw std::invalid_argument("boxes output is not float32");
  const int n = boxes.dims == 2 && boxes.cols == 4 ? boxes.rows : (boxes.total() == 0 ? 0 : -1);
  if (n < 0) throw std::invalid_argument("boxes output is " + MatShapeText(boxes) + ", expected [N, 4]");
  MaskRcnnOutputs o;
  o.boxes = n > 0 ? cv::Mat(n, 4, CV_32F, const_cast<uchar*>(boxes.ptr<uchar>())).clone() : cv::Mat(0, 4, CV_32F);
  // Labels are exported as int64; OpenCV DNN hands them over as float: rounded.
  const cv::Mat labels = Column(outs[at[1]], n, "labels output");
  o.labels = cv::Mat(n, 1, CV_32S);
  for (int i = 0; i < n; ++i) o.labels.at<int>(i, 0) = int(std::lround(labels.at<float>(i, 0)));
  o.scores = Column(outs[at[2]], n, "scores output");
  if (outs.size() == 4) {
    const cv::Mat& m = outs[at[3]];
    const bool ok = (m.dims == 4 && m.size[0] == n && m.size[1] == 1) || (m.dims == 3 && m.size[0] == n) ||
                    (n == 0 && m.total() == 0);
    if (!ok) throw std::invalid_argument("masks output is " + MatShapeText(m) + ", expected [N, 1, H, W] with N = " +
                                         std::to_string(n));
    if (m.type() != CV_32F) throw std::invalid_argument("masks output is not float32");
    o.masks = m;
  }
  return o;
}

std::vector<Candidate> DecodeMaskRcnnBoxes(const MaskRcnnOutputs& out, cv::Size image, double score_threshold,
                                           int class_count) {
  std::vector<Candidate> cands;
  for (int i = 0; i < out.boxes.rows; ++i) {
    const double score = out.scores.at<float>(i, 0);
    if (!(score > score_threshold)) continue;
    const int label = out.labels.at<int>(i, 0);
    Candidate c;
    c.class_id = class_count > 0 ? (label >= 1 && label <= class_count ? label - 1 : -1) : Coco91ToCoco80(label);
    if (c.class_id < 0) continue;
    c.score = score;
    c.x_min = out.boxes.at<float>(i, 0);
    c.y_min = out.boxes.at<float>(i, 1);
    c.x_max = out.boxes.at<float>(i, 2);
    c.y_max = out.boxes.at<float>(i, 3);
    c.anchor = i;
    ClipBox(c, image.width, image.height);
    cands.push_back(c);
  }
  return cands;
}

cv::Mat DecodeMaskRcnnMask(const MaskRcnnOutputs& out, int anchor, cv::Size image) {
  const cv::Mat& m = out.masks;
  const int h = m.size[m.dims - 2], w = m.size[m.dims - 1];
  if (h != image.height || w != image.width)
    throw std::invalid_argument("masks are " + std::to_string(w) + "x" + std::to_string(h) + ", the image " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " (torchvision pastes masks at the input size: feed the model the frame's size)");
  const cv::Mat plane(h, w, CV_32F, const_cast<uchar*>(m.ptr<uchar>()) + size_t(anchor) * h * w * sizeof(float));
  return plane >= 0.5f;
}

}  // namespace dynref::detect
