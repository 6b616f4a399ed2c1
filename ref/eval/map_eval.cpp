#include "eval/map_eval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>

#include "eval/trajectory_eval.h"
#include "geometry/point_index_3d.h"

namespace dynref {

Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  // Voronoi regions of the vertices, then the edges, then the face (Ericson 5.1.5).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;  // degenerate (zero-area) triangle
  return a + ab * (vb / denom) + ac * (vc / denom);
}

struct MeshDistance::Impl {
  std::vector<uint32_t> triangle;  // triangle of each sample
  std::unique_ptr<geometry::PointIndex3D> index;
};

namespace {

Eigen::Vector3d Vertex(const TriangleMesh& m, uint32_t i) {
  return Eigen::Vector3d(m.vertices[i][0], m.vertices[i][1], m.vertices[i][2]);
}

}  // namespace

MeshDistance::MeshDistance(const TriangleMesh& mesh, double sample_m)
    : mesh_(mesh), sample_m_(sample_m), impl_(new Impl) {
  // Barycentric grid with n subdivisions per triangle, n = ceil(longest edge / s): every point of
  // the triangle lies within s of a sample, so the true closest triangle always has a sample
  // within (nearest sample distance + s) of the query.
  std::vector<Eigen::Vector3f> samples;
  for (uint32_t t = 0; t < mesh.faces.size(); ++t) {
    const Eigen::Vector3d a = Vertex(mesh, mesh.faces[t][0]), b = Vertex(mesh, mesh.faces[t][1]), c = Vertex(mesh, mesh.faces[t][2]);
    const double edge = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(edge / sample_m)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        samples.push_back((a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n)).cast<float>());
        impl_->triangle.push_back(t);
      }
  }
  impl_->index = std::make_unique<geometry::PointIndex3D>(std::move(samples));
}

MeshDistance::~MeshDistance() { delete impl_; }

double MeshDistance::Distance(const Eigen::Vector3d& q) const {
  double d_sample = 0;
  if (impl_->index->Nearest(q, &d_sample) < 0) return std::numeric_limits<double>::infinity();
  // Far from the surface (> 10 samples) the nearest sample is within sample_m of the truth
  // (relative error < 10 %): exact distances only near it, where accuracy and ghosts are decided.
  if (d_sample > 10 * sample_m_) return d_sample;
  std::set<uint32_t> candidates;
  // + 1 mm: the samples are stored in float.
  for (int s : impl_->index->Within(q, d_sample + sample_m_ + 1e-3)) candidates.insert(impl_->triangle[static_cast<size_t>(s)]);
  double best = d_sample;
  for (uint32_t t : candidates) {
    const auto& f = mesh_.faces[t];
    best = std::min(best, (ClosestPointOnTriangle(q, Vertex(mesh_, f[0]), Vertex(mesh_, f[1]), Vertex(mesh_, f[2])) - q).norm());
  }
  return best;
}

SE3 MapToGroundTruth(const TumTrajectory& gt, const TumTrajectory& est, MapAlign mode, double* ate_rmse) {
  const AteResult ate = ComputeAte(gt, est, AteOptions{});
  if (ate_rmse) *ate_rmse = ate.stats.rmse;
  SE3 T = SE3::Identity();
  if (mode == MapAlign::kFirstCamera) {
    size_t first = 0;  // the earliest estimate pose with a ground-truth partner
    for (size_t i = 1; i < ate.matches.size(); ++i)
      if (ate.matches[i].second < ate.matches[first].second) first = i;
    T = gt.poses[ate.matches[first].first].T_wc * est.poses[ate.matches[first].second].T_wc.inverse();
  } else {
    T.linear() = ate.alignment.R;
    T.translation() = ate.alignment.t;
  }
  return T;
}

MapEvalResult EvaluateMap(const std::vector<Eigen::Vector3d>& map, const TriangleMesh& static_mesh,
                          const PointCloud& static_observed, const PointCloud& movers,
                          const MapEvalOptions& o) {
  return EvaluateMap(map, MeshDistance(static_mesh, o.sample_m), static_observed, movers, o);
}

MapEvalResult EvaluateMap(const std::vector<Eigen::Vector3d>& map, const MeshDistance& to_static,
                          const PointCloud& static_observed, const PointCloud& movers,
                          const MapEvalOptions& o) {
  MapEvalResult r;
  r.map_points = map.size();
  std::vector<Eigen::Vector3f> mover_points;
  for (const auto& p : movers) mover_points.emplace_back(p.x, p.y, p.z);
  const geometry::PointIndex3D mover_index(std::move(mover_points));
  std::vector<double> dist;
  dist.reserve(map.size());
  for (const Eigen::Vector3d& p : map) {
    const double d = to_static.Distance(p);
    dist.push_back(d);
    double dm = 0;
    if (d > o.ghost_m && mover_index.Nearest(p, &dm) >= 0 && dm <= o.ghost_m) ++r.ghosts;
  }
  if (!dist.empty()) {
    r.accuracy = ComputeErrorStats(dist);
    std::vector<double> sorted = dist;
    std::sort(sorted.begin(), sorted.end());
    const double pos = 0.95 * static_cast<double>(sorted.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(pos)), hi = std::min(lo + 1, sorted.size() - 1);
    r.accuracy_p95 = sorted[lo] + (pos - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
    r.ghost_fraction = static_cast<double>(r.ghosts) / static_cast<double>(map.size());
  }
  std::vector<Eigen::Vector3f> map_f;
  for (const Eigen::Vector3d& p : map) map_f.push_back(p.cast<float>());
  const geometry::PointIndex3D map_index(std::move(map_f));
  r.observed = static_observed.size();
  for (const auto& s : static_observed) {
    double d = 0;
    if (map_index.Nearest(Eigen::Vector3d(s.x, s.y, s.z), &d) >= 0 && d <= o.complete_m) ++r.observed_covered;
  }
  r.completeness = r.observed ? static_cast<double>(r.observed_covered) / static_cast<double>(r.observed) : 0.0;
  return r;
}

}  // namespace dynref
