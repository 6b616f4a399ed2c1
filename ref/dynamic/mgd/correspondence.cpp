#include "dynamic/mgd/correspondence.h"

#include <limits>
#include <map>

#include "core/parallel.h"
#include "dynamic/mgd/neighbour_grid.h"
#include "features/descriptor.h"

namespace dynref::mgd {

std::vector<Correspondence> MatchPrevious(const Frame& cur, const Frame& prev, double delta, double radius_px,
                                          int threads) {
  // Similarity delta on the normalised distance: Hamming / bits (ORB: 102 of 256 bits), or squared
  // L2 / 4 for unit float rows (the same number for +-1 coded bits, features/descriptor.h).
  const float max_dist = cur.descriptors.type() == CV_8U
                             ? static_cast<float>(static_cast<int>((1.0 - delta) * 8.0 * cur.descriptors.cols))
                             : static_cast<float>((1.0 - delta) * 4.0);
  std::map<int64_t, int> prev_of_point;  // map point -> first previous feature observing it
  for (size_t j = 0; j < prev.N(); ++j)
    if (prev.map_point_ids[j] >= 0 && !prev.outlier[j]) prev_of_point.emplace(prev.map_point_ids[j], static_cast<int>(j));
  const double r2 = radius_px * radius_px;
  // The window's candidates from pixel cells a bit larger than the radius (NeighbourGrid: a
  // superset in ascending j; the test below is the scan's), every j when a key is not finite.
  std::vector<Eigen::Vector3d> prev_keys(prev.N());
  for (size_t j = 0; j < prev.N(); ++j) prev_keys[j] = {prev.keys_un[j].pt.x, prev.keys_un[j].pt.y, 0.0};
  const NeighbourGrid grid(prev_keys, std::vector<bool>(prev.N(), true), radius_px * 1.01 + 1.0);
  std::vector<Correspondence> out(cur.N());
  ParallelForEach(cur.N(), threads, [&](size_t i) {
    const int fi = static_cast<int>(i);
    if (cur.IsExcluded(fi)) return;
    Correspondence& c = out[i];
    const int64_t mp = cur.outlier[i] ? -1 : cur.map_point_ids[i];
    auto it = mp >= 0 ? prev_of_point.find(mp) : prev_of_point.end();
    if (it != prev_of_point.end()) {
      const float h = features::RowDistance(cur.descriptors, fi, prev.descriptors, it->second);
      if (h <= max_dist) c = {it->second, CorrespondenceSource::kMapPoint, h};
      return;
    }
    const cv::Point2f& p = cur.keys_un[i].pt;
    float best = std::numeric_limits<float>::infinity();
    int best_j = -1;
    std::vector<uint32_t> near;
    const Eigen::Vector3d key(p.x, p.y, 0.0);
    const bool use_grid = grid.all_finite() && grid.Covers(key);
    if (use_grid) grid.Near(key, &near);
    const size_t m = use_grid ? near.size() : prev.N();
    for (size_t k = 0; k < m; ++k) {  // ascending j: ties keep the lowest index
      const size_t j = use_grid ? near[k] : k;
      const cv::Point2f& q = prev.keys_un[j].pt;
      const double du = p.x - q.x, dv = p.y - q.y;
      if (du * du + dv * dv > r2) continue;
      const float h = features::RowDistance(cur.descriptors, fi, prev.descriptors, static_cast<int>(j));
      if (h <= max_dist && h < best) best = h, best_j = static_cast<int>(j);
    }
    if (best_j >= 0) c = {best_j, CorrespondenceSource::kDescriptorWindow, best};
  });
  return out;
}

}  // namespace dynref::mgd
