// Nearest-neighbour and radius queries over 3-D points (nanoflann k-d tree). Distances are
// recomputed in double; ties go to the lower index, radius results come sorted by index
// (determinism rule: the tree's traversal order never reaches a result).
#pragma once
#include <Eigen/Core>
#include <memory>
#include <vector>

namespace dynref::geometry {

class PointIndex3D {
 public:
  explicit PointIndex3D(std::vector<Eigen::Vector3f> points);
  ~PointIndex3D();
  PointIndex3D(const PointIndex3D&) = delete;
  PointIndex3D& operator=(const PointIndex3D&) = delete;
  // Index of the nearest point and its distance; -1 and +inf when empty.
  int Nearest(const Eigen::Vector3d& q, double* distance) const;
  // Indices j (ascending) with |p_j - q| <= radius.
  std::vector<int> Within(const Eigen::Vector3d& q, double radius) const;
  size_t size() const { return points_.size(); }
  const Eigen::Vector3f& point(size_t i) const { return points_[i]; }

 private:
  struct Tree;
  std::vector<Eigen::Vector3f> points_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace dynref::geometry
