#include "detect/overlay.h"

#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cstdio>

namespace dynref::detect {
namespace {

cv::Scalar InstanceColor(int id) {
  static const cv::Scalar kPalette[] = {{60, 76, 231},  {113, 204, 46}, {219, 152, 52}, {15, 196, 241},
                                        {182, 89, 155}, {0, 84, 211},   {156, 188, 26}, {94, 73, 52},
                                        {34, 126, 230}, {133, 160, 22}};
  return kPalette[(id - 1) % 10];
}

}  // namespace

cv::Mat DrawDetections(const cv::Mat& bgr, const FrameDetections& frame, double mask_alpha) {
  cv::Mat out = bgr.clone();
  if (!frame.instance_ids.empty() && frame.instance_ids.size() == bgr.size()) {
    for (int y = 0; y < out.rows; ++y) {
      const uint16_t* ids = frame.instance_ids.ptr<uint16_t>(y);
      cv::Vec3b* px = out.ptr<cv::Vec3b>(y);
      for (int x = 0; x < out.cols; ++x) {
        if (ids[x] == 0) continue;
        const cv::Scalar c = InstanceColor(ids[x]);
        for (int k = 0; k < 3; ++k)
          px[x][k] = cv::saturate_cast<uchar>((1 - mask_alpha) * px[x][k] + mask_alpha * c[k]);
      }
    }
  }
  const double scale = std::max(0.4, std::min(out.cols, out.rows) / 900.0);
  const int thick = std::max(1, int(scale * 2 + 0.5));
  for (const DetectedInstance& d : frame.instances)
    cv::rectangle(out, cv::Point(int(d.x_min + 0.5), int(d.y_min + 0.5)),
                  cv::Point(int(d.x_max + 0.5), int(d.y_max + 0.5)), InstanceColor(d.id), thick, cv::LINE_AA);
  // Labels last, least confident first, so the most confident label stays readable on top.
  for (auto it = frame.instances.rbegin(); it != frame.instances.rend(); ++it) {
    const DetectedInstance& d = *it;
    const cv::Scalar c = InstanceColor(d.id);
    const cv::Point p0(int(d.x_min + 0.5), int(d.y_min + 0.5));
    char label[96];
    std::snprintf(label, sizeof label, "%s %.2f%s", d.class_name.c_str(), d.confidence, d.has_mask ? " m" : "");
    int baseline = 0;
    const cv::Size ts = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.5 * scale, thick, &baseline);
    const int ty = std::max(ts.height + 2, p0.y - 2);
    cv::rectangle(out, cv::Point(p0.x, ty - ts.height - 2), cv::Point(p0.x + ts.width + 2, ty + baseline - 1), c, cv::FILLED);
    cv::putText(out, label, cv::Point(p0.x + 1, ty - 1), cv::FONT_HERSHEY_SIMPLEX, 0.5 * scale,
                cv::Scalar(255, 255, 255), thick, cv::LINE_AA);
  }
  return out;
}

}  // namespace dynref::detect
