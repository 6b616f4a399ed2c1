#include "detect/person_masker.h"

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <cmath>

namespace dynref::detect {

cv::Rect PersonCropRect(const DetectedInstance& box, double enlarge) {
  const double cx = 0.5 * (box.x_min + box.x_max), cy = 0.5 * (box.y_min + box.y_max);
  const double side = enlarge * std::max(box.x_max - box.x_min, box.y_max - box.y_min);
  const int side_px = std::max(1, int(std::ceil(side)));
  const int x0 = int(std::floor(cx - 0.5 * side_px)), y0 = int(std::floor(cy - 0.5 * side_px));
  return {x0, y0, side_px, side_px};
}

cv::Mat CropWithZeroPadding(const cv::Mat& image, const cv::Rect& rect) {
  cv::Mat out = cv::Mat::zeros(rect.height, rect.width, image.type());
  const cv::Rect inside = rect & cv::Rect(0, 0, image.cols, image.rows);
  if (inside.area() > 0) image(inside).copyTo(out(inside - rect.tl()));
  return out;
}

int PaintInstanceProbability(const cv::Mat& prob, const cv::Rect& crop_rect, const cv::Rect& allowed,
                             int instance_id, double threshold, cv::Mat& instance_ids, cv::Mat& best_prob) {
  const cv::Rect region = crop_rect & allowed & cv::Rect(0, 0, instance_ids.cols, instance_ids.rows);
  int won = 0;
  for (int y = region.y; y < region.y + region.height; ++y) {
    const float* p = prob.ptr<float>(y - crop_rect.y);
    uint16_t* ids = instance_ids.ptr<uint16_t>(y);
    float* best = best_prob.ptr<float>(y);
    for (int x = region.x; x < region.x + region.width; ++x) {
      const float v = p[x - crop_rect.x];
      if (v > threshold && v > best[x]) {
        best[x] = v;
        ids[x] = uint16_t(instance_id);
        ++won;
      }
    }
  }
  return won;
}

PersonMasker::PersonMasker(LoadedModel model, PersonMaskOptions options)
    : model_(std::move(model)), options_(options) {}

cv::Mat PersonMasker::CropProbability(const cv::Mat& crop_bgr) {
  const cv::Mat blob = cv::dnn::blobFromImage(crop_bgr, 1.0 / 255.0,
                                              cv::Size(options_.input_size, options_.input_size),
                                              cv::Scalar(), /*swapRB=*/true, /*crop=*/false);
  model_.net.setInput(blob);
  const cv::Mat out = model_.net.forward();  // 1x1xSxS person probability
  const cv::Mat prob(options_.input_size, options_.input_size, CV_32F, const_cast<uchar*>(out.data));
  cv::Mat resized;
  cv::resize(prob, resized, crop_bgr.size(), 0, 0, cv::INTER_LINEAR);
  return resized;
}

void PersonMasker::AddMasks(const cv::Mat& bgr, FrameDetections& frame) {
  cv::Mat ids = cv::Mat::zeros(bgr.size(), CV_16U);
  cv::Mat best = cv::Mat::zeros(bgr.size(), CV_32F);
  bool any = false;
  for (DetectedInstance& d : frame.instances) {
    if (d.class_id != 0) continue;
    const cv::Rect crop_rect = PersonCropRect(d, options_.crop_enlarge);
    const cv::Mat prob = CropProbability(CropWithZeroPadding(bgr, crop_rect));
    const double mx = options_.box_margin * (d.x_max - d.x_min), my = options_.box_margin * (d.y_max - d.y_min);
    const int ax0 = int(std::floor(d.x_min - mx)), ay0 = int(std::floor(d.y_min - my));
    const cv::Rect allowed(ax0, ay0, int(std::ceil(d.x_max + mx)) - ax0, int(std::ceil(d.y_max + my)) - ay0);
    PaintInstanceProbability(prob, crop_rect, allowed, d.id, options_.threshold, ids, best);
    any = true;
  }
  if (!any) return;
  // Final ownership (later instances may have taken pixels of earlier ones).
  std::vector<int> count(65536, 0);
  for (int y = 0; y < ids.rows; ++y) {
    const uint16_t* row = ids.ptr<uint16_t>(y);
    for (int x = 0; x < ids.cols; ++x) ++count[row[x]];
  }
  bool any_mask = false;
  for (DetectedInstance& d : frame.instances) {
    d.has_mask = d.class_id == 0 && count[d.id] > 0;
    any_mask = any_mask || d.has_mask;
  }
  frame.instance_ids = any_mask ? ids : cv::Mat();
}

}  // namespace dynref::detect
