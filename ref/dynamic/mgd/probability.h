// MGD-SLAM (seed 000) probability formulas, pure functions (spec 000 steps 7-10; the paper's
// equations are unnumbered, cited by section). Signs inside the sigmoids were lost in the
// paper's extraction (spec E2): large residuals give a high dynamic probability.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "dynamic/mgd/options.h"

namespace dynref::mgd {

constexpr double kClampP = 1e-6;  // P is clamped to [1e-6, 1 - 1e-6] before logit (spec step 8d)

double Sigmoid(double z);
double Logit(double p);  // of the clamped p

// Sec. 3.5 short-term cue. v = x^k - x^{k-1} of the feature, vbar = mean v of the out-of-box
// features. d = ||v - vbar||; dtheta per options.angle_form (spec E5).
struct VelocityDeviation {
  double d_px = 0;
  double dtheta = 0;
};
VelocityDeviation Deviation(const Eigen::Vector2d& v, const Eigen::Vector2d& vbar, const MgdOptions& o);
// P_LS = sig(a_LS (d - d_th) + (1 - a_LS)(dtheta - theta_th)).
double ProbabilityLS(const VelocityDeviation& dev, const MgdOptions& o);
// P_pro = sig(a_pro ((dbar_fwd + dbar_bwd) / 2 - d_th_pro)).
double ProbabilityPro(double mean_forward_px, double mean_backward_px, const MgdOptions& o);
// P_mf = sig(a_mf (d_epi - d_th_mf)).
double ProbabilityMF(double epipolar_distance_px, const MgdOptions& o);

// Sec. 3.5 fusion S = sig(w_LS logit(P_LS) + w_pro logit(P_pro) + w_mf logit(P_mf)); a cue that
// is not computable (or switched off) contributes P = 0.5 (logit 0).
struct Cues {
  bool has_ls = false, has_pro = false, has_mf = false;
  double p_ls = 0.5, p_pro = 0.5, p_mf = 0.5;
};
double Fuse(const Cues& c, const MgdOptions& o);

// Sec. 3.6 weight of a kept observation (spec E13): 1 - P, or 1 with weight: none.
double KeptWeight(double p, const MgdOptions& o);

// Sec. 3.4 temporal smoothing, form per spec E1.
double Smooth(double p_prev, double s, const MgdOptions& o);

// Sec. 3.4 spatial diffusion (Jacobi: right-hand side from the input values). For each i with a
// point (has_point), neighbours j != i with a point and ||X_i - X_j|| <= r:
//   P'(i) = P(i) + C_i sum_j exp(-d_ij / r) (P(j) - P(i)),  C_i = 1 / (1 + sum_j exp(-d_ij / r))
// (spec E11 normaliser: P' stays in [0, 1]). neighbours[i] receives |N(i)|. threads (the run's
// --threads): nodes in chunks side by side; each node sums over j in ascending order, so the
// result is the same for any count.
std::vector<double> Diffuse(const std::vector<Eigen::Vector3d>& points, const std::vector<bool>& has_point,
                            const std::vector<double>& p, double radius_m, std::vector<int>* neighbours,
                            int threads = 1);

}  // namespace dynref::mgd
