#include "dense/filters.h"

#include <nanoflann.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

namespace dynref::dense {
namespace {

struct VoxelAccumulator {
  double x = 0, y = 0, z = 0;
  double r = 0, g = 0, b = 0;
  int n = 0;
  std::map<int, int> classes;  // class id -> count
};

struct CloudAdaptor {
  const PointCloud& pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(size_t i, size_t dim) const {
    return dim == 0 ? pts[i].x : (dim == 1 ? pts[i].y : pts[i].z);
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

PointCloud VoxelDownsample(const PointCloud& in, double leaf_m) {
  if (!(leaf_m > 0)) throw std::invalid_argument("voxel leaf_m must be > 0");
  std::map<std::tuple<int64_t, int64_t, int64_t>, VoxelAccumulator> voxels;
  const double inv = 1.0 / leaf_m;
  for (const ColoredPoint& p : in) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    const auto key = std::make_tuple(static_cast<int64_t>(std::floor(p.x * inv)),
                                     static_cast<int64_t>(std::floor(p.y * inv)),
                                     static_cast<int64_t>(std::floor(p.z * inv)));
    VoxelAccumulator& a = voxels[key];
    a.x += p.x, a.y += p.y, a.z += p.z;
    a.r += p.r, a.g += p.g, a.b += p.b;
    ++a.n;
    ++a.classes[p.class_id];
  }
  PointCloud out;
  out.reserve(voxels.size());
  for (const auto& [key, a] : voxels) {
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
    out.push_back(p);
  }
  return out;
}

void SorOptions::Check() const {
  if (k < 1) throw std::invalid_argument("sor k must be >= 1");
  if (!(std_mult >= 0)) throw std::invalid_argument("sor std_mult must be >= 0");
}

PointCloud StatisticalOutlierRemoval(const PointCloud& in, const SorOptions& options) {
  options.Check();
  if (in.size() <= static_cast<size_t>(options.k)) return in;
  CloudAdaptor adaptor{in};
  KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const size_t kq = static_cast<size_t>(options.k) + 1;  // + self
  std::vector<uint32_t> idx(kq);
  std::vector<float> d2(kq);
  std::vector<double> mean_dist(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const float q[3] = {in[i].x, in[i].y, in[i].z};
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
  const double n = static_cast<double>(in.size());
  const double mean = sum / n;
  const double var = std::max(0.0, (sq - sum * sum / n) / (n - 1));
  const double threshold = mean + options.std_mult * std::sqrt(var);
  PointCloud out;
  out.reserve(in.size());
  for (size_t i = 0; i < in.size(); ++i)
    if (mean_dist[i] <= threshold) out.push_back(in[i]);
  return out;
}

}  // namespace dynref::dense
