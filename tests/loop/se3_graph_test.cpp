// The loop room's solvers on planted data: the SE(3) RANSAC (se3_solver.h) recovers a known
// transform among outliers, deterministically for a seed; the essential-graph optimisation
// (essential_graph.h) closes a planted loop of poses and traces its residuals.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include "core/rng.h"
#include "loop/essential_graph.h"
#include "loop/se3_solver.h"
#include "loop/yaw_pose.h"

using namespace dynref;

namespace {

Intrinsics K() { return {535.4, 539.2, 320.1, 247.6, 40.0, 640, 480}; }

Eigen::Vector2d Project(const Eigen::Vector3d& X) {
  const Intrinsics k = K();
  return {k.fx * X.x() / X.z() + k.cx, k.fy * X.y() / X.z() + k.cy};
}

}  // namespace

TEST_CASE("SE(3) RANSAC: a planted transform is recovered among 30 % outliers, the same for the same seed") {
  const SE3 T_12 = test::YawPose(0.2, {0.1, -0.05, 0.3});
  Rng rng(3, "test.points");
  std::vector<loop::Se3Match> matches;
  for (int i = 0; i < 100; ++i) {
    loop::Se3Match m;
    m.X2 = {rng.Uniform(-1, 1), rng.Uniform(-0.8, 0.8), rng.Uniform(2, 4)};
    m.X1 = T_12 * m.X2;
    if (i % 10 < 3) m.X1 += Eigen::Vector3d(rng.Uniform(0.3, 0.6), rng.Uniform(-0.5, 0.5), 0);  // outlier
    m.uv1 = Project(m.X1);
    m.uv2 = Project(m.X2);
    matches.push_back(m);
  }
  Rng r1(1, "loop.se3"), r2(1, "loop.se3");
  const loop::Se3RansacResult a = loop::Se3Ransac(matches, K(), loop::Se3RansacOptions{}, r1);
  const loop::Se3RansacResult b = loop::Se3Ransac(matches, K(), loop::Se3RansacOptions{}, r2);
  REQUIRE(a.ok);
  CHECK(a.num_inliers == 70);
  for (int i = 0; i < 100; ++i) CHECK(a.inlier[i] == (i % 10 >= 3 ? 1 : 0));
  CHECK((a.T_12.matrix() - T_12.matrix()).norm() < 1e-9);
  CHECK(a.T_12.matrix() == b.T_12.matrix());
  CHECK(a.iterations == b.iterations);
  // Too few matches: refused.
  std::vector<loop::Se3Match> few(matches.begin(), matches.begin() + 10);
  CHECK_FALSE(loop::Se3Ransac(few, K(), loop::Se3RansacOptions{}, r1).ok);
}

TEST_CASE("essential graph: a drifted loop of poses is closed by its loop edge, residuals traced") {
  // Ground truth: 8 poses on a circle; odometry edges exact, the estimate drifted by a growing
  // offset; the loop edge 7 -> 0 carries the true relative pose; pose 0 fixed.
  std::map<int64_t, SE3> truth, drifted;
  for (int i = 0; i < 8; ++i) {
    const double a = 2 * 3.14159265358979323846 * i / 8;
    truth[i] = test::YawPose(a, {std::sin(a), 0, std::cos(a)});
    drifted[i] = test::YawPose(a + 0.01 * i, {std::sin(a) + 0.02 * i, 0.01 * i, std::cos(a)});
  }
  std::vector<loop::PoseGraphEdge> edges;
  for (int i = 1; i < 8; ++i) edges.push_back({i, i - 1, SE3(truth[i - 1] * truth[i].inverse())});
  edges.push_back({7, 0, SE3(truth[0] * truth[7].inverse())});
  drifted[0] = truth[0];
  trace::TraceWriter trace{"", trace::Level::kOff, trace::RunHeader{}};
  const loop::PoseGraphResult r = loop::OptimizePoseGraph(drifted, {0}, edges, 20, &trace, "essential#1");
  CHECK(r.chi2_start > 1e-4);
  CHECK(r.chi2_end < 1e-12);
  for (int i = 0; i < 8; ++i) CHECK((r.T_cw.at(i).matrix() - truth[i].matrix()).norm() < 1e-5);
  CHECK(r.T_cw.at(0).matrix() == truth[0].matrix());  // fixed
  // The residual of an exact edge is zero.
  const std::vector<double> e = loop::PoseGraphResidual(edges[0], truth[1], truth[0]);
  for (double v : e) CHECK(std::abs(v) < 1e-12);
  // Unknown keyframes are refused.
  std::vector<loop::PoseGraphEdge> bad{{1, 99, SE3::Identity()}};
  CHECK_THROWS(loop::OptimizePoseGraph(drifted, {0}, bad, 5, nullptr, "essential#2"));
}
