// MGD-SLAM formulas (seed 000 Sec. 3.4-3.5) against values computed by hand (python3 math):
// each fails if a sign, a weight or the smoothing direction flips.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/rng.h"
#include "dynamic/mgd/neighbour_grid.h"
#include "dynamic/mgd/probability.h"

using namespace dynref::mgd;

TEST_CASE("mgd formulas: sigmoid, clamped logit and log-odds fusion") {
  CHECK(Sigmoid(0) == 0.5);
  CHECK(Logit(0.5) == 0.0);
  CHECK(Logit(0.0) == Approx(-13.815509557963773).epsilon(1e-12));  // clamped to 1e-6
  const MgdOptions o;  // w = 0.4 / 0.4 / 0.2 (Table 1)
  Cues c;
  c.has_ls = c.has_pro = c.has_mf = true;
  c.p_ls = 0.9, c.p_pro = 0.2, c.p_mf = 0.5;
  CHECK(Fuse(c, o) == Approx(0.5803893920284022).epsilon(1e-12));
  // A cue that is not computable contributes logit 0: the same value without P_mf, whatever P_mf
  // holds (0.95 here: a Fuse that ignored has_* would give 0.7137; planted and seen failing).
  c.has_mf = false;
  c.p_mf = 0.95;
  CHECK(Fuse(c, o) == Approx(0.5803893920284022).epsilon(1e-12));
  Cues no_ls = c;  // only P_pro computable: sig(0.4 logit 0.2), P_LS 0.9 and P_mf 0.95 ignored
  no_ls.has_ls = false;
  CHECK(Fuse(no_ls, o) == Approx(0.36481689431254416).epsilon(1e-12));
  Cues no_pro = c;  // only P_LS computable
  no_pro.has_pro = false;
  CHECK(Fuse(no_pro, o) == Approx(0.7065921139768864).epsilon(1e-12));
  // Only P_pro switched off (ablation): S = sig(0.4 logit 0.9).
  MgdOptions only_ls = o;
  only_ls.use_pro = only_ls.use_mf = false;
  CHECK(Fuse(c, only_ls) == Approx(1 / (1 + std::pow(9.0, -0.4))).epsilon(1e-12));
  CHECK(Fuse(Cues{}, o) == 0.5);  // nothing computable: no evidence
}

TEST_CASE("mgd formulas: smoothing direction per spec E1") {
  MgdOptions o;  // a = 0.7
  CHECK(Smooth(0.5, 0.9, o) == Approx(0.3 * 0.5 + 0.7 * 0.9));  // (1 - a) P_prev + a S = 0.78
  o.smoothing = SmoothingForm::kOldEvidence;
  CHECK(Smooth(0.5, 0.9, o) == Approx(0.7 * 0.5 + 0.3 * 0.9));  // 0.62
}

TEST_CASE("mgd formulas: the three cues") {
  const MgdOptions o;  // d_th_LS 3 px, theta_th 2 rad, a_LS 0.5, d_th_mf = d_th_pro = 2 px, slopes 1
  // A feature moving against a 2 px background flow: d = 4, dtheta = pi.
  const VelocityDeviation dev = Deviation({-2, 0}, {2, 0}, o);
  CHECK(dev.d_px == Approx(4.0));
  CHECK(dev.dtheta == Approx(M_PI));
  CHECK(ProbabilityLS(dev, o) == Approx(0.7447483256649783).epsilon(1e-12));
  // Background flow below 0.5 px: no direction (E5), d = 5 -> sig(0.5 * 2 + 0.5 * (0 - 2)) = 0.5.
  const VelocityDeviation slow = Deviation({3, 4}, {0.1, 0}, o);
  CHECK(slow.dtheta == 0.0);
  CHECK(ProbabilityLS(slow, o) == Approx(Sigmoid(0.5 * (std::hypot(2.9, 4.0) - 3) - 1.0)));
  // Literal form (E5 switch): arctan(dv/du) of the residual (-4, 0) is 0, not pi.
  MgdOptions lit = o;
  lit.angle_form = AngleForm::kLiteralArctan;
  CHECK(Deviation({-2, 0}, {2, 0}, lit).dtheta == 0.0);
  CHECK(Deviation({2, 3}, {2, 0}, lit).dtheta == Approx(M_PI / 2));  // du = 0
  CHECK(ProbabilityMF(2.0, o) == 0.5);
  CHECK(ProbabilityMF(5.0, o) == Approx(0.9525741268224334).epsilon(1e-12));
  CHECK(ProbabilityMF(0.0, o) < 0.5);  // on the epipolar line: likely static
  CHECK(ProbabilityPro(1.0, 3.0, o) == 0.5);  // mean of forward and backward = threshold
  CHECK(ProbabilityPro(6.0, 4.0, o) == Approx(Sigmoid(3.0)));
}

TEST_CASE("mgd formulas: Jacobi diffusion of a 3-feature cluster") {
  // A and B 0.1 m apart (inside r = 0.15 m), C 0.9 m away; D has no depth.
  const std::vector<Eigen::Vector3d> X = {{0, 0, 1}, {0.1, 0, 1}, {1, 0, 1}, {0, 0, 0}};
  const std::vector<bool> has = {true, true, true, false};
  const std::vector<double> p = {0.9, 0.1, 0.5, 0.8};
  std::vector<int> nb;
  const std::vector<double> q = Diffuse(X, has, p, 0.15, &nb);
  CHECK(q[0] == Approx(0.6286050950126538).epsilon(1e-12));  // pulled towards B
  CHECK(q[1] == Approx(0.3713949049873463).epsilon(1e-12));  // pulled towards A
  CHECK(q[0] + q[1] == Approx(1.0));                         // symmetric exchange
  CHECK(q[2] == 0.5);                                        // no neighbour
  CHECK(q[3] == 0.8);                                        // no point: unchanged
  CHECK(nb == std::vector<int>{1, 1, 0, 0});
  // Jacobi: the order of the features does not matter.
  const std::vector<double> r = Diffuse({X[1], X[0], X[2], X[3]}, has, {0.1, 0.9, 0.5, 0.8}, 0.15, nullptr);
  CHECK(r[0] == q[1]);
  CHECK(r[1] == q[0]);
}

TEST_CASE("mgd diffusion: 2, 3 and 4 threads give the values of 1 (issue 18)") {
  // 600 nodes on a 0.1 m lattice (each with neighbours within r), every 7th without a point.
  std::vector<Eigen::Vector3d> X;
  std::vector<bool> has;
  std::vector<double> p;
  for (int i = 0; i < 600; ++i) {
    X.emplace_back(0.1 * (i % 10), 0.1 * ((i / 10) % 10), 1.0 + 0.1 * (i / 100));
    has.push_back(i % 7 != 0);
    p.push_back(double((i * 37) % 100) / 100.0);
  }
  std::vector<int> nb1;
  const std::vector<double> q1 = Diffuse(X, has, p, 0.15, &nb1);
  CHECK(nb1[11] > 0);
  for (int threads : {2, 3, 4}) {
    std::vector<int> nb;
    CHECK(Diffuse(X, has, p, 0.15, &nb, threads) == q1);
    CHECK(nb == nb1);
  }
}

namespace {
// The O(n^2) scan Diffuse replaced (issue 35): every j ascending.
std::vector<double> DiffuseByScan(const std::vector<Eigen::Vector3d>& X, const std::vector<bool>& has,
                                  const std::vector<double>& p, double r, std::vector<int>* nb) {
  std::vector<double> out = p;
  nb->assign(p.size(), 0);
  for (size_t i = 0; i < p.size(); ++i) {
    if (!has[i]) continue;
    double sum_w = 0, sum_wp = 0;
    for (size_t j = 0; j < p.size(); ++j) {
      if (j == i || !has[j]) continue;
      const double d2 = (X[i] - X[j]).squaredNorm();
      if (d2 > r * r) continue;
      const double w = std::exp(-std::sqrt(d2) / r);
      sum_w += w, sum_wp += w * (p[j] - p[i]), ++(*nb)[i];
    }
    out[i] = p[i] + sum_wp / (1.0 + sum_w);
  }
  return out;
}
}  // namespace

TEST_CASE("mgd diffusion: the neighbour grid gives the scan's bytes (issue 35)") {
  // Random points, pairs exactly r apart across cell borders, negative coordinates; then a NaN point
  // (the scan counts a NaN distance as a neighbour: the grid falls back to the scan).
  dynref::Rng rng(11, "mgd-grid");
  std::vector<Eigen::Vector3d> X;
  std::vector<bool> has;
  std::vector<double> p;
  for (int i = 0; i < 700; ++i) {
    X.emplace_back(rng.Uniform(-1, 1), rng.Uniform(-0.5, 0.5), rng.Uniform(0.5, 2));
    has.push_back(i % 9 != 0);
    p.push_back(rng.Uniform01());
  }
  for (int i = 0; i < 20; ++i) {
    X.emplace_back(0.1515 * i, 0.0, 1.0), has.push_back(true), p.push_back(0.05 * i);
    X.emplace_back(0.1515 * i + 0.15, 0.0, 1.0), has.push_back(true), p.push_back(1.0 - 0.05 * i);
  }
  for (bool with_nan : {false, true}) {
    if (with_nan) X[5] = {std::nan(""), 0.0, 1.0}, has[5] = true;
    std::vector<int> nb_scan, nb;
    const std::vector<double> a = DiffuseByScan(X, has, p, 0.15, &nb_scan);
    const std::vector<double> b = Diffuse(X, has, p, 0.15, &nb);
    REQUIRE(a.size() == b.size());
    CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
    CHECK(nb == nb_scan);
    CHECK(*std::max_element(nb.begin(), nb.end()) > 2);
  }
}

TEST_CASE("mgd neighbour grid: candidates are a superset of the radius, ascending") {
  std::vector<Eigen::Vector3d> X;
  for (int i = 0; i < 300; ++i) X.emplace_back(0.037 * (i % 17) - 0.3, 0.051 * (i % 13), 0.0);
  const NeighbourGrid grid(X, std::vector<bool>(X.size(), true), 0.1 * 1.01);
  CHECK(grid.all_finite());
  std::vector<uint32_t> near;
  for (size_t i = 0; i < X.size(); ++i) {
    grid.Near(X[i], &near);
    CHECK(std::is_sorted(near.begin(), near.end()));
    for (size_t j = 0; j < X.size(); ++j)
      if ((X[i] - X[j]).norm() <= 0.1) CHECK(std::binary_search(near.begin(), near.end(), uint32_t(j)));
  }
  CHECK_FALSE(NeighbourGrid({{std::nan(""), 0, 0}}, {true}, 1.0).all_finite());
  CHECK(NeighbourGrid({{std::nan(""), 0, 0}}, {false}, 1.0).all_finite());  // unused points do not count
}

TEST_CASE("mgd options: out-of-range values are named") {
  MgdOptions o;
  o.a = 1.5;
  CHECK_THROWS_WITH(o.Check(), Catch::Matchers::Contains("a (smoothing)"));
  o = MgdOptions();
  o.radius_m = 0;
  CHECK_THROWS_WITH(o.Check(), Catch::Matchers::Contains("radius_m"));
}
