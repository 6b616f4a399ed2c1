// Fixed-radius neighbour candidates for MGD's O(n^2) scans (previous-frame matching in pixels,
// the spatial diffusion in metres): points bucketed into cubic cells of side `cell`; Near(q) lists
// every point in q's cell and the 26 cells around it, in ascending index order. With `cell`
// larger than the search radius this is a superset of the points within the radius, so a caller
// that runs its original test over Near(q) in that order visits the same points in the same order
// as a scan over all indices: the same neighbours and the same sums, bit for bit.
#pragma once
#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace dynref::mgd {

class NeighbourGrid {
 public:
  // Points with use[i] false (or a non-finite or huge coordinate, above 1e9 cells: see all_finite) are left out.
  NeighbourGrid(const std::vector<Eigen::Vector3d>& points, const std::vector<bool>& use, double cell);
  // False when a used point was left out for its coordinates: the caller must scan everything (a NaN
  // distance passes a `d2 > r2` rejection test, so no grid reproduces the scan then).
  bool all_finite() const { return all_finite_; }
  // Whether q's cell can be computed (finite, within 1e9 cells); Near needs it.
  bool Covers(const Eigen::Vector3d& q) const;
  // Candidates of a covered query point, ascending; `out` is overwritten.
  void Near(const Eigen::Vector3d& q, std::vector<uint32_t>* out) const;

 private:
  struct Entry {
    int64_t x, y, z;
    uint32_t index;
  };
  int64_t Cell(double v) const;
  double cell_;
  bool all_finite_ = true;
  std::vector<Entry> entries_;  // sorted by (x, y, z, index)
};

}  // namespace dynref::mgd
