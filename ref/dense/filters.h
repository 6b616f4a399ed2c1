// Point-cloud filters of the dense map (seed 001, Sec. 3.6: "single-frame voxel downsampling",
// then "statistical outlier removal combined with voxel grid sampling"), PCL-equivalent and
// deterministic.
#pragma once
#include "dense/point_cloud.h"

namespace dynref::dense {

// Voxel grid (PCL VoxelGrid semantics): one point per occupied cubic voxel of side leaf_m, at
// the centroid of its points; colour = rounded mean colour; class_id = most frequent class of
// the voxel (ties: smallest id; -1 counts like any id). Voxel key = floor(p / leaf_m) per axis;
// output ordered by key (x, then y, then z), so the result is independent of the input order
// up to the floating-point summation order (which follows the input order).
PointCloud VoxelDownsample(const PointCloud& in, double leaf_m);

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

}  // namespace dynref::dense
