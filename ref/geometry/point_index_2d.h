// Radius queries over image points (nanoflann k-d tree, 2-D). Results come sorted by index, so
// callers sum in a fixed order whatever the tree's traversal order (determinism rule).
#pragma once
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace dynref::geometry {

class PointIndex2D {
 public:
  explicit PointIndex2D(std::vector<cv::Point2f> points);
  ~PointIndex2D();
  PointIndex2D(const PointIndex2D&) = delete;
  PointIndex2D& operator=(const PointIndex2D&) = delete;
  // Indices j (ascending) with |p_j - q| < radius (strict), and their distances.
  void Within(const cv::Point2f& q, double radius, std::vector<int>* index, std::vector<double>* distance) const;
  size_t size() const { return points_.size(); }

 private:
  struct Tree;
  std::vector<cv::Point2f> points_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace dynref::geometry
