#include "geometry/point_index_2d.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>

namespace dynref::geometry {

struct PointIndex2D::Tree {
  struct Adaptor {
    const std::vector<cv::Point2f>* pts;
    size_t kdtree_get_point_count() const { return pts->size(); }
    float kdtree_get_pt(size_t i, size_t dim) const { return dim == 0 ? (*pts)[i].x : (*pts)[i].y; }
    template <class BBOX>
    bool kdtree_get_bbox(BBOX&) const { return false; }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor>, Adaptor, 2, uint32_t>;
  Adaptor adaptor;
  Index index;
  explicit Tree(const std::vector<cv::Point2f>* pts)
      : adaptor{pts}, index(2, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    index.buildIndex();
  }
};

PointIndex2D::PointIndex2D(std::vector<cv::Point2f> points) : points_(std::move(points)) {
  if (!points_.empty()) tree_ = std::make_unique<Tree>(&points_);
}

PointIndex2D::~PointIndex2D() = default;

void PointIndex2D::Within(const cv::Point2f& q, double radius, std::vector<int>* index,
                          std::vector<double>* distance) const {
  index->clear();
  distance->clear();
  if (!tree_ || !(radius > 0)) return;
  // nanoflann works in float squared distances; query slightly wider, then decide exactly in
  // double so that a point at exactly `radius` is out whatever the float rounding.
  const float r2 = float(radius * radius) * 1.0001f + 1e-6f;
  std::vector<std::pair<uint32_t, float>> hits;
  nanoflann::SearchParams params;
  params.sorted = false;
  const float qp[2] = {q.x, q.y};
  tree_->index.radiusSearch(qp, r2, hits, params);
  std::vector<uint32_t> ids;
  ids.reserve(hits.size());
  for (const auto& h : hits) ids.push_back(h.first);
  std::sort(ids.begin(), ids.end());
  for (uint32_t j : ids) {
    const double dx = double(points_[j].x) - q.x, dy = double(points_[j].y) - q.y;
    const double d = std::sqrt(dx * dx + dy * dy);
    if (d < radius) index->push_back(int(j)), distance->push_back(d);
  }
}

}  // namespace dynref::geometry
