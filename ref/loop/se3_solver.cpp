// SE(3) RANSAC between two keyframes; see se3_solver.h.
#include "loop/se3_solver.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace dynref::loop {
namespace {

bool Reprojects(const Intrinsics& K, const Eigen::Vector3d& X_c, const Eigen::Vector2d& uv, double max_e2) {
  if (X_c.z() <= 0) return false;
  const Eigen::Vector2d p(K.fx * X_c.x() / X_c.z() + K.cx, K.fy * X_c.y() / X_c.z() + K.cy);
  return (p - uv).squaredNorm() < max_e2;
}

}  // namespace

SE3 AlignRigid(const std::vector<Eigen::Vector3d>& X1, const std::vector<Eigen::Vector3d>& X2) {
  const size_t n = X1.size();
  Eigen::Vector3d c1 = Eigen::Vector3d::Zero(), c2 = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) c1 += X1[i], c2 += X2[i];
  c1 /= static_cast<double>(n);
  c2 /= static_cast<double>(n);
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) H += (X2[i] - c2) * (X1[i] - c1).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) D(2, 2) = -1;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
  SE3 T = SE3::Identity();
  T.linear() = R;
  T.translation() = c1 - R * c2;
  return T;
}

int Se3Inliers(const std::vector<Se3Match>& matches, const Intrinsics& K, const SE3& T_12, double chi2,
               std::vector<uint8_t>* inlier) {
  const SE3 T_21 = T_12.inverse();
  inlier->assign(matches.size(), 0);
  int n = 0;
  for (size_t i = 0; i < matches.size(); ++i) {
    const Se3Match& m = matches[i];
    if (!Reprojects(K, T_12 * m.X2, m.uv1, chi2 * m.sigma2_1)) continue;
    if (!Reprojects(K, T_21 * m.X1, m.uv2, chi2 * m.sigma2_2)) continue;
    (*inlier)[i] = 1;
    ++n;
  }
  return n;
}

Se3RansacResult Se3Ransac(const std::vector<Se3Match>& matches, const Intrinsics& K, const Se3RansacOptions& options,
                          Rng& rng) {
  Se3RansacResult out;
  const int n = static_cast<int>(matches.size());
  if (n < 3 || n < options.min_inliers) return out;
  int iterations = options.max_iterations;
  if (options.min_inliers != n) {
    const double ratio = static_cast<double>(options.min_inliers) / n;
    const double it = std::ceil(std::log(1 - options.probability) / std::log(1 - std::pow(ratio, 3)));
    iterations = std::max(1, std::min(iterations, static_cast<int>(it)));
  }
  int best = -1;
  std::vector<uint8_t> best_inlier;
  for (int it = 0; it < iterations; ++it) {
    int s[3];
    for (int k = 0; k < 3; ++k) {
      do s[k] = static_cast<int>(rng.UniformInt(0, n - 1));
      while ((k > 0 && s[k] == s[0]) || (k > 1 && s[k] == s[1]));
    }
    std::vector<Eigen::Vector3d> a, b;
    for (int k : s) a.push_back(matches[k].X1), b.push_back(matches[k].X2);
    const SE3 T = AlignRigid(a, b);
    if (!T.matrix().allFinite()) continue;
    std::vector<uint8_t> inl;
    const int c = Se3Inliers(matches, K, T, options.chi2, &inl);
    ++out.iterations;
    if (c > best) {
      best = c;
      best_inlier = inl;
      out.T_12 = T;
    }
  }
  if (best < options.min_inliers) return out;
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < n; ++i)
    if (best_inlier[i]) a.push_back(matches[i].X1), b.push_back(matches[i].X2);
  const SE3 refit = AlignRigid(a, b);
  std::vector<uint8_t> inl;
  if (refit.matrix().allFinite() && Se3Inliers(matches, K, refit, options.chi2, &inl) >= best) {
    out.T_12 = refit;
    best_inlier = inl;
    best = 0;
    for (uint8_t v : inl) best += v;
  }
  out.ok = true;
  out.inlier = best_inlier;
  out.num_inliers = best;
  return out;
}

}  // namespace dynref::loop
