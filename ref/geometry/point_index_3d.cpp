#include "geometry/point_index_3d.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynref::geometry {

struct PointIndex3D::Tree {
  struct Adaptor {
    const std::vector<Eigen::Vector3f>* pts;
    size_t kdtree_get_point_count() const { return pts->size(); }
    float kdtree_get_pt(size_t i, size_t dim) const { return (*pts)[i][static_cast<int>(dim)]; }
    template <class BBOX>
    bool kdtree_get_bbox(BBOX&) const { return false; }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor>, Adaptor, 3, uint32_t>;
  Adaptor adaptor;
  Index index;
  explicit Tree(const std::vector<Eigen::Vector3f>* pts)
      : adaptor{pts}, index(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    index.buildIndex();
  }
};

PointIndex3D::PointIndex3D(std::vector<Eigen::Vector3f> points) : points_(std::move(points)) {
  if (!points_.empty()) tree_ = std::make_unique<Tree>(&points_);
}

PointIndex3D::~PointIndex3D() = default;

std::vector<int> PointIndex3D::Within(const Eigen::Vector3d& q, double radius) const {
  std::vector<int> out;
  if (!tree_ || !(radius >= 0)) return out;
  // float search slightly wider, exact decision in double.
  const float r2 = static_cast<float>(radius * radius) * 1.0001f + 1e-6f;
  std::vector<std::pair<uint32_t, float>> hits;
  nanoflann::SearchParams params;
  params.sorted = false;
  const float qp[3] = {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())};
  tree_->index.radiusSearch(qp, r2, hits, params);
  for (const auto& h : hits)
    if ((points_[h.first].cast<double>() - q).norm() <= radius) out.push_back(static_cast<int>(h.first));
  std::sort(out.begin(), out.end());
  return out;
}

int PointIndex3D::Nearest(const Eigen::Vector3d& q, double* distance) const {
  *distance = std::numeric_limits<double>::infinity();
  if (!tree_) return -1;
  uint32_t idx = 0;
  float d2 = 0;
  const float qp[3] = {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())};
  tree_->index.knnSearch(qp, 1, &idx, &d2);
  // Equal float distances: take every point as near as the found one and keep the lowest index.
  const double d = (points_[idx].cast<double>() - q).norm();
  int best = static_cast<int>(idx);
  double best_d = d;
  for (int j : Within(q, d * (1 + 1e-6) + 1e-9)) {
    const double dj = (points_[static_cast<size_t>(j)].cast<double>() - q).norm();
    if (dj < best_d || (dj == best_d && j < best)) best = j, best_d = dj;
  }
  *distance = best_d;
  return best;
}

}  // namespace dynref::geometry
