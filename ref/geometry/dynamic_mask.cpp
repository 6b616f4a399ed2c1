#include "geometry/dynamic_mask.h"

#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynref::geometry {
namespace {

bool IsDynamicClass(const DynamicMaskOptions& o, int class_id) {
  return std::find(o.dynamic_class_ids.begin(), o.dynamic_class_ids.end(), class_id) !=
         o.dynamic_class_ids.end();
}

// Binary CV_8U mask of one instance: its pixel mask, or its box when it has none.
cv::Mat InstancePixels(const FrameDetections& det, const DetectedInstance& inst, int width,
                       int height) {
  if (inst.has_mask && !det.instance_ids.empty()) {
    if (det.instance_ids.cols != width || det.instance_ids.rows != height)
      throw std::invalid_argument("instance mask: instance-id image size differs from the camera");
    return det.MaskOf(inst.id);
  }
  cv::Mat m = cv::Mat::zeros(height, width, CV_8U);
  const int x0 = std::max(0, static_cast<int>(std::floor(inst.x_min)));
  const int y0 = std::max(0, static_cast<int>(std::floor(inst.y_min)));
  const int x1 = std::min(width - 1, static_cast<int>(std::ceil(inst.x_max)));
  const int y1 = std::min(height - 1, static_cast<int>(std::ceil(inst.y_max)));
  if (x1 >= x0 && y1 >= y0) m(cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1)).setTo(255);
  return m;
}

}  // namespace

void DynamicMaskOptions::Check() const {
  if (dilation_kernel_px < 1 || dilation_kernel_px % 2 == 0)
    throw std::invalid_argument("dilation_kernel_px must be odd and >= 1");
  if (!(min_confidence >= 0.0 && min_confidence <= 1.0))
    throw std::invalid_argument("min_confidence must be in [0, 1]");
  for (int id : dynamic_class_ids)
    if (id < 0) throw std::invalid_argument("dynamic_class_ids must be COCO ids >= 0");
}

bool DynamicMask::InMask(double u, double v) const { return InstanceAt(u, v) != 0; }

int DynamicMask::InstanceAt(double u, double v) const {
  if (instance_labels.empty()) return 0;
  const int x = static_cast<int>(std::lround(u));
  const int y = static_cast<int>(std::lround(v));
  if (x < 0 || y < 0 || x >= instance_labels.cols || y >= instance_labels.rows) return 0;
  return instance_labels.at<uint16_t>(y, x);
}

namespace {

// Union of the instances accepted by `take`, dilated, lowest id first (see dynamic_mask.h).
template <typename Take>
DynamicMask BuildMask(const FrameDetections& detections, int width, int height, int dilation_kernel_px, Take take) {
  DynamicMask out;
  out.mask = cv::Mat::zeros(height, width, CV_8U);
  out.instance_labels = cv::Mat::zeros(height, width, CV_16U);
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(dilation_kernel_px, dilation_kernel_px));
  std::vector<const DetectedInstance*> order;
  for (const auto& inst : detections.instances) order.push_back(&inst);
  std::stable_sort(order.begin(), order.end(),
                   [](const DetectedInstance* a, const DetectedInstance* b) { return a->id < b->id; });
  for (const DetectedInstance* inst : order) {
    if (!take(*inst)) continue;
    cv::Mat m = InstancePixels(detections, *inst, width, height);
    if (dilation_kernel_px > 1) cv::dilate(m, m, kernel);
    // First (lowest id) label wins on overlaps.
    cv::Mat unlabeled = (m != 0) & (out.instance_labels == 0);
    out.instance_labels.setTo(cv::Scalar(inst->id), unlabeled);
    out.mask.setTo(255, m);
    out.instance_ids.push_back(inst->id);
  }
  return out;
}

}  // namespace

DynamicMask BuildDynamicMask(const FrameDetections& detections, int width, int height,
                             const DynamicMaskOptions& options) {
  options.Check();
  return BuildMask(detections, width, height, options.dilation_kernel_px, [&](const DetectedInstance& inst) {
    return IsDynamicClass(options, inst.class_id) && inst.confidence >= options.min_confidence;
  });
}

DynamicMask BuildInstanceMask(const FrameDetections& detections, int width, int height,
                              const std::set<int>& instance_ids, int dilation_kernel_px) {
  if (dilation_kernel_px < 1 || dilation_kernel_px % 2 == 0)
    throw std::invalid_argument("dilation_kernel_px must be odd and >= 1");
  return BuildMask(detections, width, height, dilation_kernel_px,
                   [&](const DetectedInstance& inst) { return instance_ids.count(inst.id) > 0; });
}

cv::Mat StaticClassLabels(const FrameDetections& detections, int width, int height,
                          const DynamicMaskOptions& options) {
  cv::Mat labels(height, width, CV_16S, cv::Scalar(-1));
  for (const auto& inst : detections.instances) {  // ascending id: later ids overwrite
    if (IsDynamicClass(options, inst.class_id) || inst.class_id < 0 ||
        inst.confidence < options.min_confidence || !inst.has_mask)
      continue;
    labels.setTo(cv::Scalar(inst.class_id), InstancePixels(detections, inst, width, height));
  }
  return labels;
}

}  // namespace dynref::geometry
