#include "dense/filters.h"

#include <nanoflann.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

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

}  // namespace

void SorOptions::Check() const {
  if (k < 1) throw std::invalid_argument("sor k must be >= 1");
  if (!(std_mult >= 0)) throw std::invalid_argument("sor std_mult must be >= 0");
}

std::vector<double> MeanKnnDistances(const PointCloud& query, const PointCloud& context, int k, double cap_m) {
  if (k < 1) throw std::invalid_argument("sor k must be >= 1");
  if (!(cap_m > 0)) throw std::invalid_argument("MeanKnnDistances: cap must be > 0");
  const CloudAdaptor adaptor{context, query};
  if (adaptor.kdtree_get_point_count() <= static_cast<size_t>(k)) return {};
  KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const size_t kq = static_cast<size_t>(k) + 1;  // + self
  const bool capped = std::isfinite(cap_m);
  const float cap2 = capped ? static_cast<float>(cap_m * cap_m) : 0.f;
  std::vector<uint32_t> idx(kq);
  std::vector<float> d2(kq);
  std::vector<float> sorted;
  std::vector<double> mean_dist(query.size());
  for (size_t i = 0; i < query.size(); ++i) {
    const ColoredPoint& p = query[i];
    const float q[3] = {p.x, p.y, p.z};
    const size_t found = tree.knnSearch(q, kq, idx.data(), d2.data());
    // Distances come sorted ascending; drop the smallest (self, distance 0). Summing the sorted
    // distances keeps the result independent of tie order among equal distances.
    sorted.assign(d2.begin(), d2.begin() + static_cast<std::ptrdiff_t>(found));
    if (capped)
      for (float& v : sorted) v = std::min(v, cap2);
    std::sort(sorted.begin(), sorted.end());
    mean_dist[i] = found > 1 ? MeanOfAscendingDistances(sorted.data() + 1, sorted.data() + found) : 0.0;
  }
  return mean_dist;
}

double MeanOfAscendingDistances(const float* begin, const float* end) {
  double sum = 0;
  for (const float* d2 = begin; d2 != end; ++d2) sum += std::sqrt(static_cast<double>(*d2));
  return sum / static_cast<double>(end - begin);
}

void SorStatistics::Add(const std::vector<double>& mean_dist) {
  for (double d : mean_dist) sum += d, sum_sq += d * d;
  n += static_cast<double>(mean_dist.size());
}

double SorStatistics::Threshold(double std_mult) const {
  if (n < 2) return std::numeric_limits<double>::infinity();
  const double mean = sum / n;
  const double var = std::max(0.0, (sum_sq - sum * sum / n) / (n - 1));
  return mean + std_mult * std::sqrt(var);
}

std::vector<uint8_t> StatisticalOutlierMask(const PointCloud& query, const PointCloud& context, const SorOptions& options) {
  options.Check();
  std::vector<uint8_t> keep(query.size(), 1);
  if (query.size() < 2) return keep;
  const std::vector<double> mean_dist = MeanKnnDistances(query, context, options.k);
  if (mean_dist.empty()) return keep;
  SorStatistics stats;
  stats.Add(mean_dist);
  const double threshold = stats.Threshold(options.std_mult);
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
