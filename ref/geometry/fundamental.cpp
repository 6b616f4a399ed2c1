#include "geometry/fundamental.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dynref::geometry {
namespace {

// Hartley normalisation: centroid to origin, mean distance sqrt(2).
Eigen::Matrix3d NormalisingTransform(const std::vector<Eigen::Vector2d>& pts) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  double mean_dist = 0;
  for (const auto& p : pts) mean_dist += (p - c).norm();
  mean_dist /= static_cast<double>(pts.size());
  const double s = mean_dist > 0 ? std::sqrt(2.0) / mean_dist : 1.0;
  Eigen::Matrix3d T;
  T << s, 0, -s * c.x(), 0, s, -s * c.y(), 0, 0, 1;
  return T;
}

// Row of the epipolar system x2^T F x1 = 0 in the row-major unknowns f11..f33.
Eigen::Matrix<double, 1, 9> EpipolarRow(const Eigen::Vector3d& x1, const Eigen::Vector3d& x2) {
  Eigen::Matrix<double, 1, 9> r;
  r << x2.x() * x1.x(), x2.x() * x1.y(), x2.x(), x2.y() * x1.x(), x2.y() * x1.y(), x2.y(), x1.x(),
      x1.y(), 1.0;
  return r;
}

Eigen::Matrix3d FromRowMajor(const Eigen::Matrix<double, 9, 1>& f) {
  Eigen::Matrix3d F;
  F << f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7), f(8);
  return F;
}

// Unit Frobenius norm, sign fixed by the first entry (in row-major order) with |.| > 1e-12.
Eigen::Matrix3d Canonical(Eigen::Matrix3d F) {
  const double n = F.norm();
  if (n > 0) F /= n;
  for (int i = 0; i < 9; ++i) {
    const double v = F(i / 3, i % 3);
    if (std::abs(v) > 1e-12) {
      if (v < 0) F = -F;
      break;
    }
  }
  return F;
}

struct Normalised {
  Eigen::Matrix3d T_prev, T_cur;
  std::vector<Eigen::Vector3d> x_prev, x_cur;
};

Normalised Normalise(const std::vector<Correspondence>& pts) {
  std::vector<Eigen::Vector2d> a, b;
  for (const auto& c : pts) {
    a.push_back(c.p_prev);
    b.push_back(c.p_cur);
  }
  Normalised n;
  n.T_prev = NormalisingTransform(a);
  n.T_cur = NormalisingTransform(b);
  for (const auto& c : pts) {
    n.x_prev.push_back(n.T_prev * c.p_prev.homogeneous());
    n.x_cur.push_back(n.T_cur * c.p_cur.homogeneous());
  }
  return n;
}

// Real roots of c3 a^3 + c2 a^2 + c1 a + c0 (degrades to quadratic/linear), ascending.
std::vector<double> RealRoots(double c3, double c2, double c1, double c0) {
  std::vector<double> roots;
  const double scale = std::max({std::abs(c3), std::abs(c2), std::abs(c1), std::abs(c0)});
  if (scale == 0) return roots;
  c3 /= scale, c2 /= scale, c1 /= scale, c0 /= scale;
  if (std::abs(c3) < 1e-12) {
    if (std::abs(c2) < 1e-12) {
      if (std::abs(c1) > 1e-12) roots.push_back(-c0 / c1);
    } else {
      const double disc = c1 * c1 - 4 * c2 * c0;
      if (disc >= 0) {
        const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
        roots.push_back(q / c2);
        if (q != 0) roots.push_back(c0 / q);
      }
    }
  } else {
    // Depressed cubic t^3 + p t + q = 0 with a = t - b/3 (Cardano / trigonometric).
    const double b = c2 / c3, c = c1 / c3, d = c0 / c3;
    const double p = c - b * b / 3.0;
    const double q = 2.0 * b * b * b / 27.0 - b * c / 3.0 + d;
    const double disc = q * q / 4.0 + p * p * p / 27.0;
    if (disc > 0) {
      const double s = std::sqrt(disc);
      roots.push_back(std::cbrt(-q / 2.0 + s) + std::cbrt(-q / 2.0 - s) - b / 3.0);
    } else if (p == 0) {
      roots.push_back(-b / 3.0);
    } else {
      const double r = 2.0 * std::sqrt(-p / 3.0);
      const double arg = std::clamp(3.0 * q / (p * r), -1.0, 1.0);
      const double phi = std::acos(arg) / 3.0;
      for (int k = 0; k < 3; ++k) roots.push_back(r * std::cos(phi - 2.0 * M_PI * k / 3.0) - b / 3.0);
    }
    // One Newton step each on the original cubic for accuracy.
    for (double& a : roots) {
      const double f = ((c3 * a + c2) * a + c1) * a + c0;
      const double df = (3 * c3 * a + 2 * c2) * a + c1;
      if (df != 0) a -= f / df;
    }
  }
  std::sort(roots.begin(), roots.end());
  return roots;
}

}  // namespace

double EpipolarDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& p_prev,
                        const Eigen::Vector2d& p_cur) {
  const Eigen::Vector3d L2 = F * p_prev.homogeneous();  // (X, Y, Z)
  const double denom = std::sqrt(L2.x() * L2.x() + L2.y() * L2.y());
  if (denom == 0) return std::numeric_limits<double>::infinity();
  return std::abs(p_cur.homogeneous().dot(L2)) / denom;
}

double SymmetricEpipolarDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& p_prev,
                                 const Eigen::Vector2d& p_cur) {
  return std::max(EpipolarDistance(F, p_prev, p_cur), EpipolarDistance(F.transpose(), p_cur, p_prev));
}

std::vector<Eigen::Matrix3d> SevenPointSolve(const std::vector<Correspondence>& seven) {
  if (seven.size() != 7) throw std::invalid_argument("SevenPointSolve needs exactly 7 points");
  const Normalised n = Normalise(seven);
  Eigen::Matrix<double, 9, 9> A = Eigen::Matrix<double, 9, 9>::Zero();  // 2 zero rows pad to square
  for (int i = 0; i < 7; ++i) A.row(i) = EpipolarRow(n.x_prev[i], n.x_cur[i]);
  Eigen::JacobiSVD<Eigen::Matrix<double, 9, 9>> svd(A, Eigen::ComputeFullV);
  const Eigen::Matrix<double, 9, 9>& V = svd.matrixV();
  // Null space of rank-7 A: the two right singular vectors of the smallest singular values.
  if (svd.singularValues()(6) < 1e-10 * svd.singularValues()(0)) return {};  // degenerate sample
  const Eigen::Matrix3d F1 = FromRowMajor(V.col(7)), F2 = FromRowMajor(V.col(8));
  // det(a F1 + (1-a) F2) = c3 a^3 + c2 a^2 + c1 a + c0, from its values at a = 0, 1, -1, 2.
  auto det_at = [&](double a) { return (a * F1 + (1 - a) * F2).determinant(); };
  const double d0 = det_at(0), d1 = det_at(1), dm1 = det_at(-1), d2 = det_at(2);
  const double c0 = d0;
  const double c2 = (d1 + dm1) / 2.0 - d0;
  const double s = (d1 - dm1) / 2.0;  // c3 + c1
  // d2 = 8 c3 + 4 c2 + 2 c1 + c0 = 6 c3 + 2 s + 4 c2 + c0
  const double c3 = (d2 - 4 * c2 - c0 - 2 * s) / 6.0;
  const double c1 = s - c3;
  std::vector<Eigen::Matrix3d> out;
  for (double a : RealRoots(c3, c2, c1, c0)) {
    const Eigen::Matrix3d Fn = a * F1 + (1 - a) * F2;
    out.push_back(Canonical(n.T_cur.transpose() * Fn * n.T_prev));
  }
  return out;
}

bool EightPointFit(const std::vector<Correspondence>& points, Eigen::Matrix3d& F) {
  if (points.size() < 8) return false;
  const Normalised n = Normalise(points);
  Eigen::Matrix<double, 9, 9> AtA = Eigen::Matrix<double, 9, 9>::Zero();
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Matrix<double, 1, 9> r = EpipolarRow(n.x_prev[i], n.x_cur[i]);
    AtA += r.transpose() * r;
  }
  Eigen::JacobiSVD<Eigen::Matrix<double, 9, 9>> svd(AtA, Eigen::ComputeFullV);
  if (svd.singularValues()(7) < 1e-14 * svd.singularValues()(0)) return false;  // 2-D null space
  Eigen::Matrix3d Fn = FromRowMajor(svd.matrixV().col(8));
  // Dynamic-size SVD (the fixed 3x3 one trips a GCC -Wmaybe-uninitialized false positive).
  const Eigen::MatrixXd Fd = Fn;
  Eigen::JacobiSVD<Eigen::MatrixXd> s3(Fd, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::VectorXd sv = s3.singularValues();
  sv(2) = 0;  // rank-2 enforcement
  Fn = s3.matrixU() * sv.asDiagonal() * s3.matrixV().transpose();
  F = Canonical(n.T_cur.transpose() * Fn * n.T_prev);
  return true;
}

void RansacOptions::Check() const {
  if (!(inlier_threshold_px > 0)) throw std::invalid_argument("inlier_threshold_px must be > 0");
  if (!(confidence > 0 && confidence < 1)) throw std::invalid_argument("confidence must be in (0, 1)");
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be >= 1");
  if (min_points < 8) throw std::invalid_argument("min_points must be >= 8");
}

namespace {
int CountInliers(const Eigen::Matrix3d& F, const std::vector<Correspondence>& pts, double th,
                 std::vector<uint8_t>* mask) {
  int count = 0;
  if (mask) mask->assign(pts.size(), 0);
  for (size_t i = 0; i < pts.size(); ++i) {
    if (SymmetricEpipolarDistance(F, pts[i].p_prev, pts[i].p_cur) <= th) {
      ++count;
      if (mask) (*mask)[i] = 1;
    }
  }
  return count;
}
}  // namespace

RansacResult RansacFundamental(const std::vector<Correspondence>& points,
                               const RansacOptions& options, Rng& rng) {
  options.Check();
  RansacResult best;
  const int n = static_cast<int>(points.size());
  best.inliers.assign(points.size(), 0);
  if (n < options.min_points) return best;
  int needed = options.max_iterations;
  std::vector<Correspondence> sample(7);
  for (int it = 0; it < needed; ++it) {
    // 7 distinct indices (rejection on duplicates; n >= 8 so this terminates quickly).
    int idx[7];
    for (int k = 0; k < 7; ++k) {
      bool dup;
      do {
        idx[k] = static_cast<int>(rng.UniformInt(0, n - 1));
        dup = std::find(idx, idx + k, idx[k]) != idx + k;
      } while (dup);
      sample[k] = points[idx[k]];
    }
    best.iterations = it + 1;
    for (const Eigen::Matrix3d& F : SevenPointSolve(sample)) {
      const int count = CountInliers(F, points, options.inlier_threshold_px, nullptr);
      if (count > best.inlier_count) {
        best.valid = true;
        best.F = F;
        best.inlier_count = count;
        const double w = static_cast<double>(count) / n;
        const double denom = std::log(1.0 - std::pow(w, 7));
        const double need = denom < 0 ? std::log(1.0 - options.confidence) / denom : 0.0;
        needed = std::min(options.max_iterations,
                          std::max(it + 1, static_cast<int>(std::ceil(std::isfinite(need) ? need : 0))));
      }
    }
  }
  if (!best.valid) return best;
  CountInliers(best.F, points, options.inlier_threshold_px, &best.inliers);
  if (options.final_refit && best.inlier_count >= 8) {
    std::vector<Correspondence> in;
    for (int i = 0; i < n; ++i)
      if (best.inliers[i]) in.push_back(points[i]);
    Eigen::Matrix3d F_refit;
    if (EightPointFit(in, F_refit)) {
      std::vector<uint8_t> mask;
      const int count = CountInliers(F_refit, points, options.inlier_threshold_px, &mask);
      if (count >= best.inlier_count) {
        best.F = F_refit;
        best.inliers = mask;
        best.inlier_count = count;
        best.refit_used = true;
      }
    }
  }
  return best;
}

Eigen::Matrix3d FundamentalFromPose(const Eigen::Matrix3d& K, const Eigen::Matrix3d& R_cur_prev,
                                    const Eigen::Vector3d& t_cur_prev) {
  Eigen::Matrix3d tx;
  tx << 0, -t_cur_prev.z(), t_cur_prev.y(), t_cur_prev.z(), 0, -t_cur_prev.x(), -t_cur_prev.y(), t_cur_prev.x(), 0;
  const Eigen::Matrix3d K_inv = K.inverse();
  return K_inv.transpose() * tx * R_cur_prev * K_inv;
}

}  // namespace dynref::geometry
