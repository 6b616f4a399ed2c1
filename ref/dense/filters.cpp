#include "dense/filters.h"

#include <nanoflann.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

namespace dynref::dense {
namespace {

// The k-d tree's view of context followed by query, without copying either cloud.
struct CloudAdaptor {
  const PointCloud& head;  // indices 0 .. head.size()-1
  const PointCloud& tail;  // then these
  const ColoredPoint& at(size_t i) const { return i < head.size() ? head[i] : tail[i - head.size()]; }
  size_t kdtree_get_point_count() const { return head.size() + tail.size(); }
  float kdtree_get_pt(size_t i, size_t dim) const {
    const ColoredPoint& p = at(i);
    return dim == 0 ? p.x : (dim == 1 ? p.y : p.z);
  }
  template <class BBOX>
  bool kdtree_get_bbox(BBOX&) const { return false; }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>, CloudAdaptor, 3, uint32_t>;

uint8_t RoundColour(double sum, int n) {
  return static_cast<uint8_t>(std::clamp(std::lround(sum / n), 0L, 255L));
}

}  // namespace

VoxelGrid::VoxelGrid(double leaf_m) : leaf_m_(leaf_m), inv_(1.0 / leaf_m) {
  if (!(leaf_m > 0)) throw std::invalid_argument("voxel leaf_m must be > 0");
}

VoxelGrid::Key VoxelGrid::KeyOf(const ColoredPoint& p) const {
  return std::make_tuple(static_cast<int64_t>(std::floor(p.x * inv_)), static_cast<int64_t>(std::floor(p.y * inv_)),
                         static_cast<int64_t>(std::floor(p.z * inv_)));
}

std::vector<VoxelGrid::Key> VoxelGrid::Keys() const {
  std::vector<Key> out;
  out.reserve(voxels_.size());
  for (const auto& kv : voxels_) out.push_back(kv.first);
  return out;
}

void VoxelGrid::Add(const PointCloud& in) {
  for (const ColoredPoint& p : in) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    Accumulator& a = voxels_[KeyOf(p)];
    a.x += p.x, a.y += p.y, a.z += p.z;
    a.r += p.r, a.g += p.g, a.b += p.b;
    ++a.n;
    ++a.classes[p.class_id];
  }
}

ColoredPoint VoxelGrid::Centroid(const Accumulator& a) {
  ColoredPoint p;
  p.x = static_cast<float>(a.x / a.n);
  p.y = static_cast<float>(a.y / a.n);
  p.z = static_cast<float>(a.z / a.n);
  p.r = RoundColour(a.r, a.n);
  p.g = RoundColour(a.g, a.n);
  p.b = RoundColour(a.b, a.n);
  int best = -1, best_count = -1;
  for (const auto& [cls, count] : a.classes)  // ascending id: first max wins
    if (count > best_count) best = cls, best_count = count;
  p.class_id = static_cast<int16_t>(best);
  return p;
}

PointCloud VoxelGrid::Cloud() const {
  PointCloud out;
  out.reserve(voxels_.size());
  for (const auto& [key, a] : voxels_) out.push_back(Centroid(a));
  return out;
}

PointCloud VoxelGrid::CentroidsIn(const std::array<float, 3>& lo, const std::array<float, 3>& hi) const {
  PointCloud out;
  const int64_t x0 = static_cast<int64_t>(std::floor(lo[0] * inv_)), x1 = static_cast<int64_t>(std::floor(hi[0] * inv_));
  const int64_t kMin = std::numeric_limits<int64_t>::min();
  for (auto it = voxels_.lower_bound(std::make_tuple(x0, kMin, kMin)); it != voxels_.end() && std::get<0>(it->first) <= x1; ++it) {
    const ColoredPoint c = Centroid(it->second);
    if (c.x >= lo[0] && c.x <= hi[0] && c.y >= lo[1] && c.y <= hi[1] && c.z >= lo[2] && c.z <= hi[2]) out.push_back(c);
  }
  return out;
}

PointCloud VoxelDownsample(const PointCloud& in, double leaf_m) {
  VoxelGrid grid(leaf_m);
  grid.Add(in);
  return grid.Cloud();
}

void SorOptions::Check() const {
  if (k < 1) throw std::invalid_argument("sor k must be >= 1");
  if (!(std_mult >= 0)) throw std::invalid_argument("sor std_mult must be >= 0");
}

std::vector<uint8_t> StatisticalOutlierMask(const PointCloud& query, const PointCloud& context, const SorOptions& options) {
  options.Check();
  const CloudAdaptor adaptor{context, query};
  std::vector<uint8_t> keep(query.size(), 1);
  if (adaptor.kdtree_get_point_count() <= static_cast<size_t>(options.k) || query.size() < 2) return keep;
  KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const size_t kq = static_cast<size_t>(options.k) + 1;  // + self
  std::vector<uint32_t> idx(kq);
  std::vector<float> d2(kq);
  std::vector<double> mean_dist(query.size());
  for (size_t i = 0; i < query.size(); ++i) {
    const ColoredPoint& p = query[i];
    const float q[3] = {p.x, p.y, p.z};
    const size_t found = tree.knnSearch(q, kq, idx.data(), d2.data());
    // Distances come sorted ascending; drop the smallest (self, distance 0). Summing the sorted
    // distances keeps the result independent of tie order among equal distances.
    std::vector<float> sorted(d2.begin(), d2.begin() + found);
    std::sort(sorted.begin(), sorted.end());
    double sum = 0;
    for (size_t j = 1; j < found; ++j) sum += std::sqrt(static_cast<double>(sorted[j]));
    mean_dist[i] = found > 1 ? sum / static_cast<double>(found - 1) : 0.0;
  }
  double sum = 0, sq = 0;
  for (double d : mean_dist) sum += d, sq += d * d;
  const double n = static_cast<double>(query.size());
  const double mean = sum / n;
  const double var = std::max(0.0, (sq - sum * sum / n) / (n - 1));
  const double threshold = mean + options.std_mult * std::sqrt(var);
  for (size_t i = 0; i < query.size(); ++i) keep[i] = mean_dist[i] <= threshold ? 1 : 0;
  return keep;
}

PointCloud StatisticalOutlierRemovalWithContext(const PointCloud& query, const PointCloud& context,
                                                const SorOptions& options) {
  const std::vector<uint8_t> keep = StatisticalOutlierMask(query, context, options);
  PointCloud out;
  out.reserve(query.size());
  for (size_t i = 0; i < query.size(); ++i)
    if (keep[i]) out.push_back(query[i]);
  return out;
}

PointCloud StatisticalOutlierRemoval(const PointCloud& in, const SorOptions& options) {
  return StatisticalOutlierRemovalWithContext(in, PointCloud(), options);
}

}  // namespace dynref::dense
