#include "geometry/rigid_ransac.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <stdexcept>

namespace dynref::geometry {

void RigidRansacOptions::Check() const {
  if (!(inlier_px > 0)) throw std::invalid_argument("inlier_px must be > 0");
  if (iterations < 1) throw std::invalid_argument("iterations must be >= 1");
  if (min_inliers < 3) throw std::invalid_argument("min_inliers must be >= 3");
}

namespace {

bool Fit(const std::vector<PointPair3D>& pairs, const std::vector<size_t>& idx, Eigen::Matrix3d& R,
         Eigen::Vector3d& t) {
  Eigen::Matrix3Xd a(3, idx.size()), b(3, idx.size());
  for (size_t k = 0; k < idx.size(); ++k) a.col(Eigen::Index(k)) = pairs[idx[k]].X_prev, b.col(Eigen::Index(k)) = pairs[idx[k]].X_cur;
  const Eigen::Matrix4d T = Eigen::umeyama(a, b, false);
  if (!T.allFinite()) return false;
  R = T.topLeftCorner<3, 3>();
  t = T.topRightCorner<3, 1>();
  return true;
}

int Score(const std::vector<PointPair3D>& pairs, const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double fx,
          double fy, double cx, double cy, double gate, std::vector<uint8_t>* in) {
  int n = 0;
  in->assign(pairs.size(), 0);
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Eigen::Vector3d X = R * pairs[i].X_prev + t;
    if (!(X.z() > 1e-6)) continue;
    const Eigen::Vector2d u(fx * X.x() / X.z() + cx, fy * X.y() / X.z() + cy);
    if ((u - pairs[i].u_cur).norm() < gate) (*in)[i] = 1, ++n;
  }
  return n;
}

}  // namespace

RigidRansacResult RigidRansac(const std::vector<PointPair3D>& pairs, double fx, double fy, double cx, double cy,
                              const RigidRansacOptions& o, Rng& rng) {
  o.Check();
  RigidRansacResult best;
  if (int(pairs.size()) < o.min_inliers) return best;
  std::vector<uint8_t> in;
  for (int it = 0; it < o.iterations; ++it) {
    std::vector<size_t> s;
    while (s.size() < 3) {
      const size_t k = size_t(rng.UniformInt(0, int64_t(pairs.size()) - 1));
      if (std::find(s.begin(), s.end(), k) == s.end()) s.push_back(k);
    }
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    if (!Fit(pairs, s, R, t)) continue;
    const int n = Score(pairs, R, t, fx, fy, cx, cy, o.inlier_px, &in);
    if (n > best.inlier_count) best.R = R, best.t = t, best.inliers = in, best.inlier_count = n;  // ties: earlier
  }
  if (best.inlier_count < o.min_inliers) return RigidRansacResult{};
  // Least-squares refit on the inliers, kept when it does not lose inliers.
  std::vector<size_t> idx;
  for (size_t i = 0; i < pairs.size(); ++i)
    if (best.inliers[i]) idx.push_back(i);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  if (Fit(pairs, idx, R, t)) {
    const int n = Score(pairs, R, t, fx, fy, cx, cy, o.inlier_px, &in);
    if (n >= best.inlier_count) best.R = R, best.t = t, best.inliers = in, best.inlier_count = n;
  }
  best.valid = true;
  return best;
}

}  // namespace dynref::geometry
