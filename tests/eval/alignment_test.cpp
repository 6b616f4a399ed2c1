// Closed-form alignment and statistics cases.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include "core/rng.h"
#include "eval/alignment.h"
#include "eval/statistics.h"

using namespace dynref;

namespace {
std::vector<Eigen::Vector3d> RandomPoints(int n, const std::string& stream) {
  Rng rng(7, stream);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i) p.emplace_back(rng.Uniform(-2, 2), rng.Uniform(-1, 1), rng.Uniform(0, 3));
  return p;
}
}  // namespace

TEST_CASE("alignment: statistics match numpy definitions") {
  const ErrorStats s = ComputeErrorStats({3.0, 1.0, 4.0, 2.0});
  CHECK(s.count == 4);
  CHECK(s.sse == 30.0);
  CHECK(s.rmse == Approx(std::sqrt(7.5)).epsilon(1e-15));
  CHECK(s.mean == 2.5);
  CHECK(s.median == 2.5);  // mean of the two middle values
  CHECK(s.std == Approx(std::sqrt(1.25)).epsilon(1e-15));  // population (ddof = 0)
  CHECK(s.min == 1.0);
  CHECK(s.max == 4.0);
  CHECK(ComputeErrorStats({5.0, 1.0, 2.0}).median == 2.0);
}

TEST_CASE("alignment: recovers a known rigid transform and a known similarity") {
  const std::vector<Eigen::Vector3d> est = RandomPoints(50, "test.align.points");
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -1.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(1.5, -0.3, 2.0);
  std::vector<Eigen::Vector3d> gt, gt_scaled;
  for (const auto& p : est) {
    gt.push_back(R * p + t);
    gt_scaled.push_back(2.5 * (R * p) + t);
  }
  const Similarity3 se3 = AlignPoints(est, gt, AlignMode::kSE3);
  CHECK((se3.R - R).norm() < 1e-12);
  CHECK((se3.t - t).norm() < 1e-12);
  CHECK(se3.scale == 1.0);
  const Similarity3 sim3 = AlignPoints(est, gt_scaled, AlignMode::kSim3);
  CHECK((sim3.R - R).norm() < 1e-12);
  CHECK((sim3.t - t).norm() < 1e-12);
  CHECK(sim3.scale == Approx(2.5).epsilon(1e-12));
  const Similarity3 none = AlignPoints(est, gt, AlignMode::kNone);
  CHECK(none.R == Eigen::Matrix3d::Identity());
  CHECK(none.t == Eigen::Vector3d::Zero());
  // A reflection is never returned.
  std::vector<Eigen::Vector3d> mirrored;
  for (const auto& p : est) mirrored.emplace_back(-p.x(), p.y(), p.z());
  CHECK(AlignPoints(est, mirrored, AlignMode::kSE3).R.determinant() == Approx(1.0));
  CHECK_THROWS(AlignPoints({est[0], est[1]}, {gt[0], gt[1]}, AlignMode::kSE3));
}

TEST_CASE("alignment: sim3 on coincident estimate points says why and what to use instead") {
  const std::vector<Eigen::Vector3d> est(4, Eigen::Vector3d(1, 2, 3));
  const std::vector<Eigen::Vector3d> gt = RandomPoints(4, "test.align.coincide");
  CHECK_THROWS_WITH(AlignPoints(est, gt, AlignMode::kSim3),
                    Catch::Contains("--align sim3: all 4 associated estimate positions coincide") &&
                        Catch::Contains("--align se3 or none"));
  CHECK_NOTHROW(AlignPoints(est, gt, AlignMode::kSE3));  // no scale: a constant estimate is fine
}
