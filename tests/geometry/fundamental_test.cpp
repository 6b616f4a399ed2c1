#include <catch2/catch.hpp>

#include "geometry/fundamental.h"
#include "two_view.h"

using namespace dynref::geometry;
namespace geo = dynref::geometry::testgeo;

namespace {
double FDistance(Eigen::Matrix3d a, Eigen::Matrix3d b) {
  a /= a.norm();
  b /= b.norm();
  return std::min((a - b).norm(), (a + b).norm());
}
}  // namespace

TEST_CASE("fundamental: Eq. (5) epipolar distance matches the point-line distance") {
  // F maps P1 to the line y = 2 (0 x + 1 y - 2 = 0) whatever P1 is.
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  F(1, 2) = 1;
  F(2, 2) = -2;
  CHECK(EpipolarDistance(F, {5, 7}, {10, 5}) == Approx(3.0));
  CHECK(EpipolarDistance(F, {5, 7}, {-3, 2}) == Approx(0.0).margin(1e-12));
  CHECK(std::isinf(EpipolarDistance(Eigen::Matrix3d::Zero(), {1, 1}, {1, 1})));
}

TEST_CASE("fundamental: the true F has zero epipolar distance for static points") {
  const geo::Scene s = geo::MakeScene(50, 0, 0, 1);
  const Eigen::Matrix3d F = geo::TrueF();
  for (const auto& c : s.pairs) CHECK(EpipolarDistance(F, c.p_prev, c.p_cur) < 1e-6);
}

TEST_CASE("fundamental: the 7-point solver recovers the true F among its roots") {
  const geo::Scene s = geo::MakeScene(7, 0, 0, 2);
  const std::vector<Eigen::Matrix3d> sols = SevenPointSolve(s.pairs);
  REQUIRE(!sols.empty());
  REQUIRE(sols.size() <= 3);
  double best = 1e9;
  for (const auto& F : sols) {
    best = std::min(best, FDistance(F, geo::TrueF()));
    CHECK(std::abs(F.determinant()) < 1e-8);  // rank 2
    for (const auto& c : s.pairs) CHECK(EpipolarDistance(F, c.p_prev, c.p_cur) < 1e-6);
  }
  CHECK(best < 1e-6);
}

TEST_CASE("fundamental: the 8-point fit recovers F from noise-free points") {
  const geo::Scene s = geo::MakeScene(40, 0, 0, 3);
  Eigen::Matrix3d F;
  REQUIRE(EightPointFit(s.pairs, F));
  CHECK(FDistance(F, geo::TrueF()) < 1e-6);
  CHECK(!EightPointFit(std::vector<Correspondence>(s.pairs.begin(), s.pairs.begin() + 7), F));
}

TEST_CASE("fundamental: RANSAC separates 30% moving points and is seed-deterministic") {
  const geo::Scene s = geo::MakeScene(140, 60, 0.15, 4);
  RansacOptions opt;
  dynref::Rng rng1(7, "sgdo.F"), rng2(7, "sgdo.F");
  const RansacResult r1 = RansacFundamental(s.pairs, opt, rng1);
  const RansacResult r2 = RansacFundamental(s.pairs, opt, rng2);
  REQUIRE(r1.valid);
  CHECK(r1.F == r2.F);
  CHECK(r1.inliers == r2.inliers);
  CHECK(r1.iterations == r2.iterations);
  CHECK(FDistance(r1.F, geo::TrueF()) < 1e-6);
  int static_in = 0, moving_dyn = 0;
  for (size_t i = 0; i < s.pairs.size(); ++i) {
    const double d = EpipolarDistance(r1.F, s.pairs[i].p_prev, s.pairs[i].p_cur);
    if (!s.moving[i] && d < 1e-6) ++static_in;
    if (s.moving[i] && d > 1.0) ++moving_dyn;
  }
  CHECK(static_in == 140);
  CHECK(moving_dyn >= 54);  // >= 90 %: a few move along their epipolar line (the paper's P5)
}

TEST_CASE("fundamental: RANSAC with pixel noise keeps static points under 1 px") {
  geo::Scene s = geo::MakeScene(150, 50, 0.15, 5);
  dynref::Rng noise(5, "test.noise");
  for (auto& c : s.pairs) {
    c.p_cur += Eigen::Vector2d(noise.Gaussian(0, 0.2), noise.Gaussian(0, 0.2));
    c.p_prev += Eigen::Vector2d(noise.Gaussian(0, 0.2), noise.Gaussian(0, 0.2));
  }
  dynref::Rng rng(11, "sgdo.F");
  const RansacResult r = RansacFundamental(s.pairs, RansacOptions{}, rng);
  REQUIRE(r.valid);
  int static_ok = 0;
  for (size_t i = 0; i < 150; ++i)
    if (EpipolarDistance(r.F, s.pairs[i].p_prev, s.pairs[i].p_cur) < 1.0) ++static_ok;
  CHECK(static_ok >= 145);
}

TEST_CASE("fundamental: too few points give no model") {
  const geo::Scene s = geo::MakeScene(7, 0, 0, 6);
  dynref::Rng rng(1, "sgdo.F");
  const RansacResult r = RansacFundamental(s.pairs, RansacOptions{}, rng);
  CHECK(!r.valid);
  CHECK(r.inliers.size() == 7);
  RansacOptions bad;
  bad.confidence = 1.0;
  CHECK_THROWS(bad.Check());
}

TEST_CASE("fundamental: F from a known relative pose has zero epipolar distance for static points") {
  const Eigen::Matrix3d K = geo::K();
  const Eigen::Isometry3d T = geo::RelativePose();
  const Eigen::Matrix3d F = FundamentalFromPose(K, T.linear(), T.translation());
  // A planted point at 2.5 m in the previous camera, seen in both images.
  const Eigen::Vector3d X_prev(0.3, -0.2, 2.5);
  const Eigen::Vector3d X_cur = T * X_prev;
  const Eigen::Vector3d a = K * X_prev, b = K * X_cur;
  const Eigen::Vector2d p_prev = a.hnormalized(), p_cur = b.hnormalized();
  CHECK(EpipolarDistance(F, p_prev, p_cur) < 1e-9);
  // Moved by 5 px perpendicular to the epipolar line: the distance is 5 px.
  const Eigen::Vector3d l = F * p_prev.homogeneous();
  const Eigen::Vector2d n = Eigen::Vector2d(l.x(), l.y()).normalized();
  CHECK(EpipolarDistance(F, p_prev, p_cur + 5.0 * n) == Approx(5.0).epsilon(1e-9));
  // A pure rotation has no epipolar geometry: F = 0 (distance +inf by Eq. (5)'s convention).
  CHECK(FundamentalFromPose(K, T.linear(), Eigen::Vector3d::Zero()).norm() == 0.0);
}
