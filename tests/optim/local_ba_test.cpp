// LocalBundleAdjust (ORB-SLAM2 LocalBundleAdjustment semantics) on a synthetic local map.
#include <catch2/catch.hpp>
#include <cstring>

#include "core/error.h"
#include "optim/optim.h"
#include "optim/synthetic_problem.h"

using namespace dynref;
using namespace dynref::optim;

namespace {

SyntheticBASpec SmallSpec() {
  SyntheticBASpec spec;
  spec.num_keyframes = 6;
  spec.num_fixed = 2;
  spec.num_points = 300;
  spec.views_per_point = 4;
  spec.outlier_ratio = 0.03;
  return spec;
}

std::map<int64_t, SE3> InitialPoses(const SyntheticBAProblem& p) {
  std::map<int64_t, SE3> T;
  for (const BAKeyFrame& kf : p.keyframes) T[kf.id] = kf.T_cw;
  return T;
}
std::map<int64_t, Eigen::Vector3d> InitialPoints(const SyntheticBAProblem& p) {
  std::map<int64_t, Eigen::Vector3d> X;
  for (const BAPoint& pt : p.points) X[pt.id] = pt.X_w;
  return X;
}
bool BaBitIdentical(const SE3& a, const SE3& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

}  // namespace

TEST_CASE("local-ba: reduces reprojection error, flags outliers, keeps fixed keyframes fixed") {
  const SyntheticBAProblem p = MakeSyntheticBAProblem(SmallSpec());
  const Intrinsics K = SyntheticIntrinsics();
  std::vector<uint8_t> true_inliers(p.is_outlier.size());
  for (size_t i = 0; i < p.is_outlier.size(); ++i) true_inliers[i] = !p.is_outlier[i];
  const double rms_before =
      RmsReprojectionPx(K, InitialPoses(p), InitialPoints(p), p.observations, true_inliers);
  const LocalBAResult r =
      LocalBundleAdjust(K, p.keyframes, p.points, p.observations, LocalBAOptions{}, nullptr, "t");
  // Over the observations kept as inliers (an outlier can drag a weakly constrained point during
  // the robust phase and take its other observations with it, as in ORB-SLAM2).
  std::vector<uint8_t> kept(p.is_outlier.size());
  for (size_t i = 0; i < kept.size(); ++i) kept[i] = true_inliers[i] && r.inlier[i];
  const double rms_after = RmsReprojectionPx(K, r.T_cw, r.X_w, p.observations, kept);
  INFO("rms before " << rms_before << " px, after " << rms_after << " px");
  CHECK(rms_after < 0.5 * rms_before);
  CHECK(rms_after < 1.5);  // noise 0.5 px * 1.2^octave, octave 0..7 => about 1.1 px

  for (const BAKeyFrame& kf : p.keyframes) {
    if (kf.fixed) CHECK(BaBitIdentical(r.T_cw.at(kf.id), kf.T_cw));
  }
  // Free keyframes move towards the truth.
  for (size_t k = 0; k < p.keyframes.size(); ++k) {
    if (p.keyframes[k].fixed) continue;
    const double before = (p.keyframes[k].T_cw.translation() - p.T_cw_true[k].translation()).norm();
    const double after =
        (r.T_cw.at(p.keyframes[k].id).translation() - p.T_cw_true[k].translation()).norm();
    CHECK(after < before);
  }
  REQUIRE(r.inlier.size() == p.observations.size());
  int missed = 0, rejected = 0, inliers = 0;
  for (size_t i = 0; i < r.inlier.size(); ++i) {
    if (p.is_outlier[i] && r.inlier[i]) ++missed;
    if (!p.is_outlier[i] && !r.inlier[i]) ++rejected;
    inliers += r.inlier[i];
  }
  CHECK(r.num_inliers == inliers);
  CHECK(missed <= 1);  // a random pixel can land within the chi2 gate by chance
  CHECK(rejected <= static_cast<int>(r.inlier.size() * 3 / 100));
}

TEST_CASE("local-ba: two calls are bit-identical") {
  const SyntheticBAProblem p = MakeSyntheticBAProblem(SmallSpec());
  const Intrinsics K = SyntheticIntrinsics();
  const LocalBAResult a =
      LocalBundleAdjust(K, p.keyframes, p.points, p.observations, LocalBAOptions{}, nullptr, "t");
  const LocalBAResult b =
      LocalBundleAdjust(K, p.keyframes, p.points, p.observations, LocalBAOptions{}, nullptr, "t");
  CHECK(a.T_cw.size() == p.keyframes.size());
  CHECK(a.X_w.size() == p.points.size());
  CHECK(a.inlier.size() == p.observations.size());
  REQUIRE(b.T_cw.size() == a.T_cw.size());
  REQUIRE(b.X_w.size() == a.X_w.size());
  for (const auto& [id, T] : a.T_cw) CHECK(BaBitIdentical(T, b.T_cw.at(id)));
  for (const auto& [id, X] : a.X_w)
    CHECK(std::memcmp(X.data(), b.X_w.at(id).data(), sizeof(double) * 3) == 0);
  CHECK(a.inlier == b.inlier);
}

TEST_CASE("local-ba: weight-0 observations have no influence") {
  const SyntheticBAProblem p = MakeSyntheticBAProblem(SmallSpec());
  const Intrinsics K = SyntheticIntrinsics();
  std::vector<BAObservation> obs = p.observations;
  const size_t n = obs.size();
  for (size_t i = 0; i < 200; ++i) {  // corrupted duplicates of existing observations
    BAObservation o = p.observations[i * 3];
    o.uv += Eigen::Vector2d(9.0, -7.0);
    o.weight = 0.0;
    obs.push_back(o);
  }
  const LocalBAResult base =
      LocalBundleAdjust(K, p.keyframes, p.points, p.observations, LocalBAOptions{}, nullptr, "t");
  const LocalBAResult zero =
      LocalBundleAdjust(K, p.keyframes, p.points, obs, LocalBAOptions{}, nullptr, "t");
  CHECK(base.T_cw.size() == p.keyframes.size());
  CHECK(base.X_w.size() == p.points.size());
  REQUIRE(zero.T_cw.size() == base.T_cw.size());
  REQUIRE(zero.X_w.size() == base.X_w.size());
  REQUIRE(base.inlier.size() == n);
  REQUIRE(zero.inlier.size() == obs.size());
  for (const auto& [id, T] : base.T_cw) CHECK(BaBitIdentical(T, zero.T_cw.at(id)));
  for (const auto& [id, X] : base.X_w)
    CHECK(std::memcmp(X.data(), zero.X_w.at(id).data(), sizeof(double) * 3) == 0);
  for (size_t i = 0; i < n; ++i) CHECK(base.inlier[i] == zero.inlier[i]);
}

TEST_CASE("local-ba: unknown ids and duplicate keyframes are bad input") {
  const SyntheticBAProblem p = MakeSyntheticBAProblem(SmallSpec());
  const Intrinsics K = SyntheticIntrinsics();
  std::vector<BAObservation> obs = p.observations;
  obs[0].kf_id = 99999;
  CHECK_THROWS_AS(LocalBundleAdjust(K, p.keyframes, p.points, obs, LocalBAOptions{}, nullptr, "t"),
                  InputError);
  std::vector<BAKeyFrame> kfs = p.keyframes;
  kfs.push_back(kfs[0]);
  CHECK_THROWS_AS(
      LocalBundleAdjust(K, kfs, p.points, p.observations, LocalBAOptions{}, nullptr, "t"),
      InputError);
}

TEST_CASE("local-ba: all keyframes fixed moves only points, no observations is a no-op") {
  SyntheticBASpec spec = SmallSpec();
  spec.num_fixed = spec.num_keyframes;
  const SyntheticBAProblem p = MakeSyntheticBAProblem(spec);
  const Intrinsics K = SyntheticIntrinsics();
  const LocalBAResult r =
      LocalBundleAdjust(K, p.keyframes, p.points, p.observations, LocalBAOptions{}, nullptr, "t");
  for (const BAKeyFrame& kf : p.keyframes) CHECK(BaBitIdentical(r.T_cw.at(kf.id), kf.T_cw));
  // The objective (reprojection error over kept observations) drops to the noise level; point
  // positions themselves are only as good as the depth/triangulation noise allows.
  std::vector<uint8_t> kept(p.is_outlier.size());
  for (size_t i = 0; i < kept.size(); ++i) kept[i] = !p.is_outlier[i] && r.inlier[i];
  const double rms_before =
      RmsReprojectionPx(K, InitialPoses(p), InitialPoints(p), p.observations, kept);
  const double rms_after = RmsReprojectionPx(K, r.T_cw, r.X_w, p.observations, kept);
  INFO("rms before " << rms_before << " px, after " << rms_after << " px");
  CHECK(rms_after < 0.5 * rms_before);
  CHECK(rms_after < 1.5);

  const LocalBAResult empty =
      LocalBundleAdjust(K, p.keyframes, p.points, {}, LocalBAOptions{}, nullptr, "t");
  CHECK(empty.inlier.empty());
  for (const BAPoint& pt : p.points) CHECK(empty.X_w.at(pt.id) == pt.X_w);
}

TEST_CASE("local-ba: a down-weighted observation with a large error is an outlier (unweighted test, issue 21)") {
  SyntheticBASpec spec;
  spec.outlier_ratio = 0;
  spec.noise_px = 0;
  spec.num_points = 300;
  SyntheticBAProblem p = MakeSyntheticBAProblem(spec);
  BAObservation& moving = p.observations[11];
  moving.uv.x() += 5;
  if (moving.u_right >= 0) moving.u_right += 5;
  moving.weight = 0.1;
  moving.inv_sigma2 = 1;
  LocalBAOptions o;
  const LocalBAResult r = LocalBundleAdjust(SyntheticIntrinsics(), p.keyframes, p.points, p.observations, o, nullptr, "t");
  CHECK_FALSE(r.inlier[11]);
  o.weighted_outlier_test = true;
  const LocalBAResult w = LocalBundleAdjust(SyntheticIntrinsics(), p.keyframes, p.points, p.observations, o, nullptr, "t");
  CHECK(w.inlier[11]);
}
