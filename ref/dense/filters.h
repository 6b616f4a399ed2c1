// Point-cloud filters of the dense map (seed 001, Sec. 3.6: "single-frame voxel downsampling",
// then "statistical outlier removal combined with voxel grid sampling"), PCL-equivalent and
// deterministic.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

#include "dense/point_cloud.h"

namespace dynref::dense {

// Voxel grid (PCL VoxelGrid semantics): one point per occupied cubic voxel of side leaf_m, at
// the centroid of its points; colour = rounded mean colour; class_id = most frequent class of
// the voxel (ties: smallest id; -1 counts like any id). Voxel key = floor(p / leaf_m) per axis;
// output ordered by key (x, then y, then z), so the result is independent of the input order
// up to the floating-point summation order (which follows the input order).
PointCloud VoxelDownsample(const PointCloud& in, double leaf_m);

// The same voxel grid, filled incrementally: Cloud() after Add(a), Add(b) equals
// VoxelDownsample(a + b) exactly (accumulation in add order). Used by the dense map to grow a
// global map without re-voxelising it (issue 18).
class VoxelGrid {
 public:
  using Key = std::tuple<int64_t, int64_t, int64_t>;
  explicit VoxelGrid(double leaf_m);  // std::invalid_argument unless leaf_m > 0
  void Add(const PointCloud& points);
  Key KeyOf(const ColoredPoint& p) const;  // floor(p / leaf_m) per axis (finite points)
  std::vector<Key> Keys() const;           // key order (the order of Cloud())
  PointCloud Cloud() const;           // key order, as VoxelDownsample
  size_t size() const { return voxels_.size(); }
  // Centroids of the voxels whose centroid lies inside [lo, hi] (per axis); cost proportional to
  // the voxels in the x-slab of the box, not to the whole grid.
  PointCloud CentroidsIn(const std::array<float, 3>& lo, const std::array<float, 3>& hi) const;

 private:
  struct Accumulator {
    double x = 0, y = 0, z = 0;
    double r = 0, g = 0, b = 0;
    int n = 0;
    std::map<int, int> classes;  // class id -> count
  };
  static ColoredPoint Centroid(const Accumulator& a);
  double leaf_m_, inv_;
  std::map<Key, Accumulator> voxels_;
};

struct SorOptions {
  int k = 50;              // k_sor, not stated: PCL tutorial value
  double std_mult = 1.0;   // not stated: PCL tutorial value
  void Check() const;
};

// Statistical outlier removal (PCL StatisticalOutlierRemoval semantics): for each point the mean
// distance to its k nearest neighbours (self excluded, nanoflann k-d tree); a point is an
// outlier iff its mean distance > mu + std_mult * sigma over all points (sigma: sample std).
// Keeps input order. Clouds with <= k points are returned unchanged. The k-NN distance SET is
// unique, so tie order inside the tree does not change the result.
PointCloud StatisticalOutlierRemoval(const PointCloud& in, const SorOptions& options);

// SOR of new points against a map (issue 18, dense map `incremental`): the mean k-NN distance of
// each `query` point is taken over context + query (self excluded), the threshold from the query
// points' mean and sample std; returns the kept query points in order. Without context this is
// StatisticalOutlierRemoval(query). Fewer than k + 1 points in all, or fewer than 2 queries:
// query unchanged.
PointCloud StatisticalOutlierRemovalWithContext(const PointCloud& query, const PointCloud& context,
                                                const SorOptions& options);
// The same decision as a mask over `query` (1 = kept).
std::vector<uint8_t> StatisticalOutlierMask(const PointCloud& query, const PointCloud& context, const SorOptions& options);

}  // namespace dynref::dense
