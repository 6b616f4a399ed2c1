// Points of a voxel grid bucketed in cubic bricks of B x B x B voxels, and SOR's k-NN statistic
// looked up in the 27 bricks around a point instead of a k-d tree over the whole cloud (issue 18:
// the dense map judges a few thousand new voxels per filter against a map of millions; building
// a tree over the map each time made the cost grow with the map).
//
// Coverage: a point's voxel key differs from another's by at most floor(d / leaf) + 1 per axis
// when they are d apart (centroids lie inside their voxels), and the 27 bricks around a voxel's
// brick hold every key within B of it. With B = ceil(R / leaf) + 1 they therefore hold every
// point within R, so the statistic below is exact for neighbour distances capped at R.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "dense/voxel_grid.h"

namespace dynref::dense {

class VoxelBricks {
 public:
  struct Point {
    float x, y, z;
    uint32_t id;
  };
  // Bricks of ceil(radius_m / leaf_m) + 1 voxels: every point within radius_m of a point lies in
  // the 27 bricks around its brick. std::invalid_argument unless both are > 0.
  VoxelBricks(double leaf_m, double radius_m);
  VoxelKey BrickOf(const VoxelKey& voxel) const;
  // Adds point `id` (ids 0, 1, 2, ... in insertion order) of voxel `voxel` at `pos`.
  void Add(const VoxelKey& voxel, const std::array<float, 3>& pos);
  void Move(uint32_t id, const std::array<float, 3>& pos);  // a voxel's centroid moved
  const std::vector<Point>* Find(const VoxelKey& brick) const;
  size_t size() const { return where_.size(); }
  size_t bricks() const { return members_.size(); }
  const VoxelKey& brick_key(uint32_t b) const { return bricks_.key(b); }
  const std::vector<Point>& brick_members(uint32_t b) const { return members_[b]; }
  int64_t voxels_per_brick() const { return voxels_per_brick_; }
  double leaf_m() const { return leaf_m_; }

 private:
  int64_t voxels_per_brick_;
  double leaf_m_;
  KeyHash bricks_;
  std::vector<std::vector<Point>> members_;             // per brick, insertion order
  ChunkedVector<std::pair<uint32_t, uint32_t>> where_;  // id -> (brick, slot)
};

// SOR's statistic of every point of `queries` (ids 0 .. n-1) with neighbour distances capped at
// R: the mean over its k nearest neighbours in queries + `others` of min(d, R), neighbours
// missing when fewer than k lie within R counted at R; the point itself is excluded. Equal to
// MeanKnnDistances(..., cap_m = R) whenever the sets hold more than k points in all: the
// distances are the k-d tree's (float squared differences summed x, y, z), sorted, then their
// square roots summed in double. Queries are processed brick by brick: the 27 bricks around a
// brick are gathered once for all its points. All sets must share leaf and radius
// (std::invalid_argument otherwise). Returns out[id]. threads (the run's --threads): bricks side
// by side, each point's value computed alone, so the same for any count.
std::vector<double> CappedMeanKnnDistances(const VoxelBricks& queries, const std::vector<const VoxelBricks*>& others,
                                           int k, double cap_m, int threads = 1);

}  // namespace dynref::dense
