// Point-cloud filters of the dense map (seed 001, Sec. 3.6: "single-frame voxel downsampling",
// then "statistical outlier removal combined with voxel grid sampling"), PCL-equivalent and
// deterministic.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "dense/point_cloud.h"
#include "dense/voxel_grid.h"  // VoxelGrid, VoxelDownsample

namespace dynref::dense {

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

// SOR's per-point statistic: mean distance of each query point to its k nearest neighbours in
// context + query (self excluded), each distance capped at cap_m (the incremental dense map's
// reading, issue 18; infinity = PCL). Empty when context + query has <= k points.
std::vector<double> MeanKnnDistances(const PointCloud& query, const PointCloud& context, int k,
                                     double cap_m = std::numeric_limits<double>::infinity());

// Mean of the square roots of ascending squared distances [begin, end) (non-empty), summed in
// double in that order: the one summation both k-NN paths (k-d tree, VoxelBricks) use, so their
// statistics agree bit for bit.
double MeanOfAscendingDistances(const float* begin, const float* end);

// Running mean and sample variance of SOR's mean k-NN distances: the dense map's incremental mode
// keeps those of the map's voxels, so new voxels are judged against the whole cloud's
// distribution (what SOR over the whole cloud would use) without recomputing it.
struct SorStatistics {
  double n = 0, sum = 0, sum_sq = 0;
  void Add(const std::vector<double>& mean_dist);
  // mean + std_mult * sample std; +inf with fewer than 2 samples (nothing can be judged).
  double Threshold(double std_mult) const;
};

}  // namespace dynref::dense
