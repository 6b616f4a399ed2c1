#include "dynamic/mgd/probability.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/parallel.h"
#include "dynamic/mgd/neighbour_grid.h"

namespace dynref::mgd {

void MgdOptions::Check() const {
  auto in01 = [](double v) { return v >= 0 && v <= 1; };
  if (!in01(min_confidence)) throw std::invalid_argument("min_confidence must be in [0, 1]");
  if (threshold_scale != "detector" && threshold_scale != "raw")
    throw std::invalid_argument("threshold_scale must be 'detector' or 'raw'");
  if (!in01(p_init_box) || !in01(p_init_free)) throw std::invalid_argument("p_init must be in [0, 1]");
  if (!in01(delta)) throw std::invalid_argument("delta must be in [0, 1]");
  if (!(match_radius_px > 0)) throw std::invalid_argument("match_radius_px must be > 0");
  if (!in01(a_ls)) throw std::invalid_argument("a_ls must be in [0, 1]");
  if (!(a_pro > 0) || !(a_mf > 0)) throw std::invalid_argument("sigmoid slopes a_pro, a_mf must be > 0");
  if (w_ls < 0 || w_pro < 0 || w_mf < 0) throw std::invalid_argument("fusion weights must be >= 0");
  if (!in01(a)) throw std::invalid_argument("a (smoothing) must be in [0, 1]");
  if (!(radius_m > 0)) throw std::invalid_argument("radius_m must be > 0");
  if (!in01(tau_dyn)) throw std::invalid_argument("tau_dyn must be in [0, 1]");
  if (min_velocity_px < 0) throw std::invalid_argument("min_velocity_px must be >= 0");
  if (!(line_match_angle_deg > 0 && line_match_angle_deg < 90))
    throw std::invalid_argument("line_match_angle_deg must be in (0, 90)");
  if (!(line_match_radius_px > 0)) throw std::invalid_argument("line_match_radius_px must be > 0");
  if (line_match_bits < 0 || line_match_bits > 256) throw std::invalid_argument("line_match_bits must be in [0, 256]");
}

double Sigmoid(double z) { return 1.0 / (1.0 + std::exp(-z)); }

double Logit(double p) {
  const double q = std::min(std::max(p, kClampP), 1.0 - kClampP);
  return std::log(q / (1.0 - q));
}

VelocityDeviation Deviation(const Eigen::Vector2d& v, const Eigen::Vector2d& vbar, const MgdOptions& o) {
  VelocityDeviation dev;
  const Eigen::Vector2d r = v - vbar;
  dev.d_px = r.norm();
  if (o.angle_form == AngleForm::kLiteralArctan) {
    // arctan(dv/du) of the residual (spec E5 literal form); du = 0 -> +-pi/2.
    dev.dtheta = r.x() == 0 ? (r.y() == 0 ? 0.0 : std::copysign(M_PI / 2, r.y())) : std::atan(r.y() / r.x());
  } else if (v.norm() >= o.min_velocity_px && vbar.norm() >= o.min_velocity_px) {
    const double c = v.dot(vbar) / (v.norm() * vbar.norm());
    dev.dtheta = std::acos(std::min(1.0, std::max(-1.0, c)));  // [0, pi]
  }
  return dev;
}

double ProbabilityLS(const VelocityDeviation& dev, const MgdOptions& o) {
  return Sigmoid(o.a_ls * (dev.d_px - o.d_th_ls_px) + (1.0 - o.a_ls) * (dev.dtheta - o.theta_th_ls_rad));
}

double ProbabilityPro(double mean_forward_px, double mean_backward_px, const MgdOptions& o) {
  return Sigmoid(o.a_pro * (0.5 * (mean_forward_px + mean_backward_px) - o.d_th_pro_px));
}

double ProbabilityMF(double epipolar_distance_px, const MgdOptions& o) {
  return Sigmoid(o.a_mf * (epipolar_distance_px - o.d_th_mf_px));
}

double Fuse(const Cues& c, const MgdOptions& o) {
  double z = 0;
  if (c.has_ls && o.use_ls) z += o.w_ls * Logit(c.p_ls);
  if (c.has_pro && o.use_pro) z += o.w_pro * Logit(c.p_pro);
  if (c.has_mf && o.use_mf) z += o.w_mf * Logit(c.p_mf);
  return Sigmoid(z);
}

double KeptWeight(double p, const MgdOptions& o) { return o.weight == WeightForm::kOneMinusP ? 1.0 - p : 1.0; }

double Smooth(double p_prev, double s, const MgdOptions& o) {
  return o.smoothing == SmoothingForm::kNewEvidence ? (1.0 - o.a) * p_prev + o.a * s : o.a * p_prev + (1.0 - o.a) * s;
}

std::vector<double> Diffuse(const std::vector<Eigen::Vector3d>& points, const std::vector<bool>& has_point,
                            const std::vector<double>& p, double radius_m, std::vector<int>* neighbours,
                            int threads) {
  const size_t n = p.size();
  if (points.size() != n || has_point.size() != n) throw std::invalid_argument("Diffuse: size mismatch");
  std::vector<double> out = p;
  if (neighbours) neighbours->assign(n, 0);
  const double r2 = radius_m * radius_m;
  // Candidates from cells a bit larger than r (NeighbourGrid: a superset of the nodes within r, in
  // ascending j), or every j when a point is not finite; the test and the sums are the scan's.
  const NeighbourGrid grid(points, has_point, radius_m * 1.01);
  ParallelForEach(n, threads, [&](size_t i) {
    if (!has_point[i]) return;
    std::vector<uint32_t> near;
    if (grid.all_finite()) grid.Near(points[i], &near);
    const size_t m = grid.all_finite() ? near.size() : n;
    double sum_w = 0, sum_wp = 0;
    int count = 0;
    for (size_t k = 0; k < m; ++k) {  // ascending j: a fixed summation order
      const size_t j = grid.all_finite() ? near[k] : k;
      if (j == i || !has_point[j]) continue;
      const double d2 = (points[i] - points[j]).squaredNorm();
      if (d2 > r2) continue;
      const double w = std::exp(-std::sqrt(d2) / radius_m);
      sum_w += w;
      sum_wp += w * (p[j] - p[i]);
      ++count;
    }
    out[i] = p[i] + sum_wp / (1.0 + sum_w);
    if (neighbours) (*neighbours)[i] = count;
  });
  return out;
}

}  // namespace dynref::mgd
