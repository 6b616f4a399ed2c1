#include "dynamic/mgd/neighbour_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace dynref::mgd {

NeighbourGrid::NeighbourGrid(const std::vector<Eigen::Vector3d>& points, const std::vector<bool>& use, double cell)
    : cell_(cell) {
  if (!(cell > 0) || !std::isfinite(cell)) throw std::invalid_argument("NeighbourGrid: cell must be > 0");
  if (use.size() != points.size()) throw std::invalid_argument("NeighbourGrid: size mismatch");
  entries_.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::Vector3d& p = points[i];
    if (!Covers(p)) {
      all_finite_ = false;
      continue;
    }
    entries_.push_back({Cell(p.x()), Cell(p.y()), Cell(p.z()), uint32_t(i)});
  }
  std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
    return std::tie(a.x, a.y, a.z, a.index) < std::tie(b.x, b.y, b.z, b.index);
  });
}

bool NeighbourGrid::Covers(const Eigen::Vector3d& q) const {
  return q.allFinite() && !(q.array().abs() / cell_ > 1e9).any();  // far out: cell indices lose precision
}

int64_t NeighbourGrid::Cell(double v) const { return int64_t(std::floor(v / cell_)); }

void NeighbourGrid::Near(const Eigen::Vector3d& q, std::vector<uint32_t>* out) const {
  out->clear();
  const int64_t cx = Cell(q.x()), cy = Cell(q.y()), cz = Cell(q.z());
  const auto before = [](const Entry& e, const std::tuple<int64_t, int64_t, int64_t>& k) {
    return std::tie(e.x, e.y, e.z) < k;
  };
  for (int64_t x = cx - 1; x <= cx + 1; ++x)
    for (int64_t y = cy - 1; y <= cy + 1; ++y) {  // cells (x, y, cz-1..cz+1) are one sorted run
      auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_tuple(x, y, cz - 1), before);
      for (; it != entries_.end() && it->x == x && it->y == y && it->z <= cz + 1; ++it) out->push_back(it->index);
    }
  std::sort(out->begin(), out->end());
}

}  // namespace dynref::mgd
