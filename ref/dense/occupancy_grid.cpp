#include "dense/occupancy_grid.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/atomic_file.h"
#include "core/format.h"
#include "core/rng.h"

namespace dynref::dense {

FloorPlane FitFloor(const PointCloud& cloud, const FloorOptions& o) {
  FloorPlane best;
  const int n = static_cast<int>(cloud.size());
  if (n < 3) return best;
  const Eigen::Vector3d up = o.up_hint.normalized();
  const double cos_tilt = std::cos(o.max_tilt_deg * M_PI / 180.0);
  auto P = [&](int i) { return Eigen::Vector3d(cloud[i].x, cloud[i].y, cloud[i].z); };
  // Hypotheses are drawn from the lowest points along up_hint (the floor is below everything),
  // and scored on at most max_scored points (every stride-th), so the cost does not grow with the
  // map; the final count is made on the same subsample.
  std::vector<std::pair<double, int>> height(n);
  for (int i = 0; i < n; ++i) height[i] = {up.dot(P(i)), i};
  std::stable_sort(height.begin(), height.end());
  const int low = std::max(3, static_cast<int>(o.low_fraction * n));
  const int stride = std::max(1, n / o.max_scored);
  Rng rng(o.seed, "semantic.floor");
  for (int it = 0; it < o.iterations; ++it) {
    const int a = height[rng.UniformInt(0, low - 1)].second, b = height[rng.UniformInt(0, low - 1)].second,
              c = height[rng.UniformInt(0, low - 1)].second;
    Eigen::Vector3d nrm = (P(b) - P(a)).cross(P(c) - P(a));
    if (nrm.norm() < 1e-9) continue;
    nrm.normalize();
    if (nrm.dot(up) < 0) nrm = -nrm;
    if (nrm.dot(up) < cos_tilt) continue;
    const double d = -nrm.dot(P(a));
    int inliers = 0, below = 0, scored = 0;
    for (int i = 0; i < n; i += stride, ++scored) {
      const double h = nrm.dot(P(i)) + d;
      inliers += std::abs(h) <= o.inlier_m;
      below += h < -o.inlier_m;
    }
    if (below > o.max_below_fraction * scored || inliers <= best.inliers) continue;
    best.found = true, best.n = nrm, best.d = d, best.inliers = inliers;
  }
  return best;
}

OccupancyGrid BuildOccupancyGrid(const PointCloud& cloud, const FloorPlane& floor, const GridOptions& o) {
  OccupancyGrid g;
  g.cell_m = o.cell_m;
  const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(floor.n, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector2d> xy;
  for (const ColoredPoint& p : cloud) {
    const Eigen::Vector3d w(p.x, p.y, p.z);
    const double h = floor.n.dot(w) + floor.d;
    if (h < o.h_min_m || h > o.h_max_m) continue;
    const Eigen::Vector3d q = R * w;
    xy.emplace_back(q.x(), q.y());
  }
  g.points_used = static_cast<int64_t>(xy.size());
  if (xy.empty()) return g;
  Eigen::Vector2d lo = xy[0], hi = xy[0];
  for (const auto& v : xy) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  g.origin_x = std::floor(lo.x() / o.cell_m) * o.cell_m;
  g.origin_y = std::floor(lo.y() / o.cell_m) * o.cell_m;
  g.width = static_cast<int>(std::floor((hi.x() - g.origin_x) / o.cell_m)) + 1;
  g.height = static_cast<int>(std::floor((hi.y() - g.origin_y) / o.cell_m)) + 1;
  g.occupied.assign(static_cast<size_t>(g.width) * g.height, 0);
  for (const auto& v : xy) {
    const int ix = std::min(g.width - 1, static_cast<int>(std::floor((v.x() - g.origin_x) / o.cell_m)));
    const int iy = std::min(g.height - 1, static_cast<int>(std::floor((v.y() - g.origin_y) / o.cell_m)));
    uint8_t& c = g.occupied[static_cast<size_t>(iy) * g.width + ix];
    g.occupied_cells += c == 0;
    c = 1;
  }
  return g;
}

void WriteMapServer(const OccupancyGrid& g, const std::string& pgm_path, const std::string& yaml_path) {
  {
    AtomicOutputFile out(pgm_path, true);
    out.stream() << "P5\n" << g.width << " " << g.height << "\n255\n";
    for (int row = 0; row < g.height; ++row) {  // row 0 of the image = the largest y
      const int iy = g.height - 1 - row;
      for (int ix = 0; ix < g.width; ++ix)
        out.stream().put(static_cast<char>(g.occupied[static_cast<size_t>(iy) * g.width + ix] ? 0 : 254));
    }
    out.Commit();
  }
  std::ostringstream y;
  y << "image: " << std::filesystem::path(pgm_path).filename().string() << "\n"
    << "resolution: " << FormatDouble17(g.cell_m) << "\n"
    << "origin: [" << FormatDouble17(g.origin_x) << ", " << FormatDouble17(g.origin_y) << ", 0.0]\n"
    << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n";
  AtomicWriteFile(yaml_path, y.str());
}

}  // namespace dynref::dense
