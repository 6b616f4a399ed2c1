#include "dynamic/semantic/interaction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynref::semantic {
std::map<int, cv::Rect> InstanceBounds(const cv::Mat& ids) {
  std::map<int, cv::Vec4i> box;  // x0 y0 x1 y1
  for (int y = 0; y < ids.rows; ++y) {
    const uint16_t* row = ids.ptr<uint16_t>(y);
    for (int x = 0; x < ids.cols; ++x) {
      if (row[x] == 0) continue;
      auto [it, fresh] = box.emplace(row[x], cv::Vec4i(x, y, x, y));
      if (!fresh) {
        cv::Vec4i& b = it->second;
        b[0] = std::min(b[0], x), b[1] = std::min(b[1], y), b[2] = std::max(b[2], x), b[3] = std::max(b[3], y);
      }
    }
  }
  std::map<int, cv::Rect> out;
  for (const auto& [id, b] : box) out[id] = cv::Rect(b[0], b[1], b[2] - b[0] + 1, b[3] - b[1] + 1);
  return out;
}

InteractionResult TestInteraction(const cv::Mat& ids, const cv::Mat& depth, const std::map<int, cv::Rect>& bounds,
                                  int id_a, int id_b, int d_max, double t_int_m) {
  if (ids.type() != CV_16U || depth.type() != CV_32F || ids.size() != depth.size())
    throw std::invalid_argument("TestInteraction: need CV_16U ids and CV_32F depth of one size");
  InteractionResult r;
  const auto ia = bounds.find(id_a), ib = bounds.find(id_b);
  if (ia == bounds.end() || ib == bounds.end()) return r;
  const cv::Rect a = ia->second, b = ib->second;
  // Only pixels of A within d_max of B's box can pair.
  const cv::Rect near_b = (b - cv::Point(d_max, d_max) + cv::Size(2 * d_max, 2 * d_max)) & cv::Rect(0, 0, ids.cols, ids.rows);
  const cv::Rect scan = a & near_b;
  double sum = 0;
  const int d2 = d_max * d_max;
  for (int y = scan.y; y < scan.y + scan.height; ++y) {
    for (int x = scan.x; x < scan.x + scan.width; ++x) {
      if (ids.at<uint16_t>(y, x) != id_a) continue;
      const float za = depth.at<float>(y, x);
      if (!(za > 0)) continue;
      for (int v = std::max(0, y - d_max); v <= std::min(ids.rows - 1, y + d_max); ++v)
        for (int u = std::max(0, x - d_max); u <= std::min(ids.cols - 1, x + d_max); ++u) {
          if ((u - x) * (u - x) + (v - y) * (v - y) > d2 || ids.at<uint16_t>(v, u) != id_b) continue;
          const float zb = depth.at<float>(v, u);
          if (!(zb > 0)) continue;
          sum += std::abs(static_cast<double>(za) - zb);
          ++r.pairs;
        }
    }
  }
  if (r.pairs > 0) r.dz_mean_m = sum / r.pairs;
  r.interacting = r.pairs > 0 && r.dz_mean_m < t_int_m;
  return r;
}

}  // namespace dynref::semantic
