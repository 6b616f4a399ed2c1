// ATE and RPE on closed-form cases: a known rigid transform plus known noise.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/error.h"
#include "core/rng.h"
#include "eval/trajectory_eval.h"

using namespace dynref;

namespace {

TumTrajectory Make(const std::string& name, const std::vector<StampedPose>& poses) {
  TumTrajectory t;
  t.path = name;
  t.poses = poses;
  for (size_t i = 0; i < poses.size(); ++i) t.lines.push_back(int(i) + 1);
  return t;
}

// A wiggly ground-truth trajectory at 30 Hz (stamps exact multiples of 1/32 s).
std::vector<StampedPose> GroundTruth(int n) {
  std::vector<StampedPose> gt(n);
  for (int i = 0; i < n; ++i) {
    const double s = i / 32.0;
    gt[i].stamp = 100.0 + s;
    gt[i].T_wc = MakeSE3(Eigen::Vector3d(std::sin(s), 0.5 * std::cos(0.7 * s), 0.2 * s),
                         Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * std::sin(s), Eigen::Vector3d::UnitY())));
  }
  return gt;
}

}  // namespace

TEST_CASE("ate: rigid transform plus radial noise of known size") {
  // gt_i = T (p_i + s (p_i - mean)): the optimal SE(3) alignment is exactly T (the
  // cross-covariance is (1 + s) Cov(p), symmetric positive definite), so error_i = |s| |p_i - mean|.
  const std::vector<StampedPose> base = GroundTruth(64);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : base) mean += p.T_wc.translation();
  mean /= base.size();
  const double s = 0.01;
  const SE3 T = MakeSE3(Eigen::Vector3d(3, -2, 1), Eigen::Quaterniond(Eigen::AngleAxisd(
                                                       1.1, Eigen::Vector3d(1, 1, 0).normalized())));
  std::vector<StampedPose> gt = base, est = base;
  std::vector<double> expected;
  for (size_t i = 0; i < base.size(); ++i) {
    const Eigen::Vector3d p = base[i].T_wc.translation();
    gt[i].T_wc = T * base[i].T_wc;
    gt[i].T_wc.translation() = T * (p + s * (p - mean));
    expected.push_back(s * (p - mean).norm());
  }
  AteOptions opt;
  const AteResult r = ComputeAte(Make("gt", gt), Make("est", est), opt);
  REQUIRE(r.matches.size() == 64);
  const ErrorStats want = ComputeErrorStats(expected);
  CHECK(r.stats.rmse == Approx(want.rmse).epsilon(1e-9));
  CHECK(r.stats.max == Approx(want.max).epsilon(1e-9));
  CHECK(r.stats.median == Approx(want.median).epsilon(1e-9));
  // Sim(3) absorbs the radial noise completely: scale 1 + s, zero error.
  opt.align = AlignMode::kSim3;
  const AteResult sim = ComputeAte(Make("gt", gt), Make("est", est), opt);
  CHECK(sim.alignment.scale == Approx(1 + s).epsilon(1e-12));
  CHECK(sim.stats.max < 1e-12);
  // No alignment: the error is the whole transform.
  opt.align = AlignMode::kNone;
  CHECK(ComputeAte(Make("gt", gt), Make("est", est), opt).stats.min > 1.0);
}

TEST_CASE("ate: association drops stamps without partner and zero pairs is an input error") {
  std::vector<StampedPose> gt = GroundTruth(40), est = GroundTruth(40);
  for (auto& p : est) p.stamp += 0.0078125;  // 7.8 ms offset: still associated
  est.erase(est.begin() + 10, est.begin() + 20);  // gap
  AteOptions opt;
  const AteResult r = ComputeAte(Make("gt", gt), Make("est", est), opt);
  CHECK(r.matches.size() == 30);
  for (auto& p : est) p.stamp += 1000.0;
  try {
    ComputeAte(Make("gt.txt", gt), Make("est.txt", est), opt);
    FAIL("zero pairs accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("est.txt") != std::string::npos);
    CHECK(std::string(e.what()).find("zero associated pairs") != std::string::npos);
  }
}

TEST_CASE("rpe: known translation and rotation noise") {
  // gt: identity rotations; est: positions + n_i, rotations Rz(theta_i). With delta = 1 frame
  // the pairs are (i, i+1) for i + 1 < last, E = dEst dGt^-1, so
  // trans = |n_{i+1} - n_i| and rot = |theta_{i+1} - theta_i| (rotations only on est).
  const int n = 40;
  Rng rng(3, "test.rpe.noise");
  std::vector<StampedPose> gt(n), est(n), rot_est(n);
  std::vector<Eigen::Vector3d> noise(n);
  std::vector<double> theta(n);
  for (int i = 0; i < n; ++i) {
    gt[i].stamp = est[i].stamp = rot_est[i].stamp = 10.0 + i / 32.0;
    gt[i].T_wc.translation() = Eigen::Vector3d(0.1 * i, 0.02 * i * i, 0.0);
    noise[i] = Eigen::Vector3d(rng.Gaussian(0, 0.01), rng.Gaussian(0, 0.01), rng.Gaussian(0, 0.01));
    est[i].T_wc.translation() = gt[i].T_wc.translation() + noise[i];
    theta[i] = rng.Uniform(-0.05, 0.05);
    rot_est[i].T_wc.linear() = Eigen::AngleAxisd(theta[i], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  RpeOptions opt;
  opt.delta = 1;
  opt.unit = DeltaUnit::kFrames;
  const RpeResult r = ComputeRpe(Make("gt", gt), Make("est", est), opt);
  REQUIRE(r.pairs.size() == size_t(n - 2));  // j == last index is dropped, as the TUM tool
  std::vector<double> want_t;
  for (int i = 0; i + 2 < n; ++i) want_t.push_back((noise[i + 1] - noise[i]).norm());
  for (size_t k = 0; k < r.pairs.size(); ++k) {
    CHECK(r.pairs[k].est_0 == k);
    CHECK(r.pairs[k].est_1 == k + 1);
    CHECK(r.pairs[k].trans_m == Approx(want_t[k]).margin(1e-12));
  }
  CHECK(r.trans_m.rmse == Approx(ComputeErrorStats(want_t).rmse).epsilon(1e-9));

  std::vector<StampedPose> gt0(n);
  for (int i = 0; i < n; ++i) gt0[i].stamp = gt[i].stamp;
  const RpeResult rr = ComputeRpe(Make("gt", gt0), Make("est", rot_est), opt);
  REQUIRE(rr.pairs.size() == size_t(n - 2));
  for (size_t k = 0; k < rr.pairs.size(); ++k) {
    CHECK(rr.pairs[k].rot_rad == Approx(std::abs(theta[k + 1] - theta[k])).margin(1e-9));
    CHECK(rr.pairs[k].trans_m < 1e-12);
  }
  // A rigid change of world frame on the estimate leaves RPE at zero (delta in seconds).
  const SE3 G = MakeSE3(Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond(Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitX())));
  std::vector<StampedPose> moved = gt;
  for (auto& p : moved) p.T_wc = G * p.T_wc;
  RpeOptions sec;
  sec.delta = 0.25;
  const RpeResult zero = ComputeRpe(Make("gt", gt), Make("est", moved), sec);
  CHECK(zero.pairs.size() == size_t(n - 8 - 1));
  CHECK(zero.trans_m.max < 1e-12);
  CHECK(zero.rot_deg.max < 1e-6);
}

TEST_CASE("rpe: pairs whose ground truth is too far are dropped") {
  std::vector<StampedPose> gt = GroundTruth(64), est = GroundTruth(64);
  gt.erase(gt.begin() + 20, gt.begin() + 30);  // gt gap of 10 frames
  const RpeResult r = ComputeRpe(Make("gt", gt), Make("est", est), {1.0 / 32.0 * 2, DeltaUnit::kSeconds});
  CHECK(r.gt_median_interval_s == 1.0 / 32.0);
  CHECK(r.candidate_pairs == 64 - 3);  // j = i + 2; i = 61, 62, 63 reach the last index
  // Estimate stamps 22..27 are more than 2/32 s from every gt stamp (gt 20..29 removed).
  // Dropped: i = 20..27 (est_0 or est_1 = i + 2 lands in 22..27); 2/32 s exactly is kept.
  CHECK(r.pairs.size() == r.candidate_pairs - 8);
  for (const RpePair& p : r.pairs) {
    CHECK(std::abs(gt[p.gt_0].stamp - est[p.est_0].stamp) <= 2.0 / 32.0);
    CHECK(std::abs(gt[p.gt_1].stamp - est[p.est_1].stamp) <= 2.0 / 32.0);
  }
}

TEST_CASE("rpe: TUM find_closest_index") {
  const std::vector<double> L = {1.0, 2.0, 3.0, 4.0};
  CHECK(TumFindClosestIndex(L, 0.0) == 0);
  CHECK(TumFindClosestIndex(L, 2.0) == 1);
  CHECK(TumFindClosestIndex(L, 2.4) == 1);
  CHECK(TumFindClosestIndex(L, 2.6) == 2);
  CHECK(TumFindClosestIndex(L, 9.0) == 3);
  // Exact tie at 2.5: the tool keeps the first visited (middle = 2 -> index 2), then index 1 is
  // not strictly closer.
  CHECK(TumFindClosestIndex(L, 2.5) == 2);
}

TEST_CASE("ate and rpe: --offset undoes a constant stamp shift of the estimate") {
  // Ground truth at 32 Hz on a moving trajectory; the estimate is every other gt pose with its
  // stamp labelled 1/32 s late. Without an offset each estimate is compared with the gt pose one
  // sample later (non-zero errors); offset = -1/32 s pairs it with the pose it was copied from.
  const std::vector<StampedPose> gt = GroundTruth(96);
  std::vector<StampedPose> est;
  for (size_t i = 0; i + 1 < gt.size(); i += 2) {
    est.push_back(gt[i]);
    est.back().stamp = gt[i + 1].stamp;
  }
  const TumTrajectory g = Make("gt", gt), e = Make("est", est);
  RpeOptions rpe;
  rpe.delta = 1;
  rpe.unit = DeltaUnit::kFrames;
  AteOptions ate;
  const RpeResult shifted = ComputeRpe(g, e, rpe);
  const AteResult ate_shifted = ComputeAte(g, e, ate);
  CHECK(shifted.rot_deg.max > 0.01);
  CHECK(ate_shifted.stats.rmse > 1e-3);
  rpe.offset_s = ate.offset_s = -1.0 / 32.0;
  const RpeResult undone = ComputeRpe(g, e, rpe);
  const AteResult ate_undone = ComputeAte(g, e, ate);
  REQUIRE(undone.pairs.size() == shifted.pairs.size());  // pair selection ignores the offset
  for (const RpePair& p : undone.pairs) CHECK(p.gt_0 == 2 * p.est_0);
  CHECK(undone.trans_m.max < 1e-12);
  CHECK(undone.rot_deg.max < 1e-5);  // acos near 1: ~1e-8 rad of rounding
  CHECK(ate_undone.matches.size() == est.size());
  CHECK(ate_undone.stats.rmse < 1e-9);
  rpe.offset_s = std::nan("");
  CHECK_THROWS_AS(ComputeRpe(g, e, rpe), InputError);
  rpe.offset_s = 0;
  rpe.delta = 1e17;  // stamp + delta loses the stamps' precision: rejected, not nonsense pairs
  CHECK_THROWS_AS(ComputeRpe(g, e, rpe), InputError);
}

TEST_CASE("rpe interp: ground truth interpolated at the stamps, last pair kept, gaps dropped") {
  // Constant velocity and constant angular velocity about a fixed axis: lerp and slerp between
  // any two samples are exact, so estimates sampled between ground-truth stamps score zero.
  auto pose_at = [](double t) {
    StampedPose p;
    p.stamp = t;
    p.T_wc = MakeSE3(Eigen::Vector3d(0.5 * t, -0.2 * t, 0.1 * t),
                     Eigen::Quaterniond(Eigen::AngleAxisd(0.8 * t, Eigen::Vector3d(1, 2, 3).normalized())));
    return p;
  };
  std::vector<StampedPose> gt, est;
  for (int i = 0; i < 200; ++i) gt.push_back(pose_at(i / 100.0));
  for (int i = 0; i < 40; ++i) est.push_back(pose_at(0.013 + i / 30.0));
  RpeOptions opt;
  opt.delta = 1;
  opt.unit = DeltaUnit::kFrames;
  opt.mode = RpeMode::kInterp;
  const RpeResult r = ComputeRpe(Make("gt", gt), Make("est", est), opt);
  CHECK(RpeModeName(opt.mode) == std::string("interp"));
  REQUIRE(r.pairs.size() == est.size() - 1);  // the pair ending at the last pose is kept
  CHECK(r.pairs.back().est_1 == est.size() - 1);
  CHECK(r.pairs[3].gt_stamp_0 == est[3].stamp);
  CHECK(r.trans_m.max < 1e-12);
  CHECK(r.rot_deg.max < 1e-5);
  opt.mode = RpeMode::kTum;  // nearest ground truth: up to 5 ms away, so non-zero errors
  const RpeResult tum = ComputeRpe(Make("gt", gt), Make("est", est), opt);
  CHECK(tum.pairs.size() == est.size() - 2);
  CHECK(tum.trans_m.max > 1e-4);
  // A ground-truth gap of 60 ms (> 2 x 10 ms) drops the pairs with a stamp inside it.
  std::vector<StampedPose> gapped;
  for (const StampedPose& p : gt)
    if (p.stamp < 0.30 || p.stamp > 0.355) gapped.push_back(p);
  opt.mode = RpeMode::kInterp;
  const RpeResult g = ComputeRpe(Make("gt", gapped), Make("est", est), opt);
  CHECK(g.candidate_pairs == est.size() - 1);
  for (const RpePair& p : g.pairs) {
    CHECK(!(p.gt_stamp_0 > 0.29 && p.gt_stamp_0 < 0.36));
    CHECK(!(p.gt_stamp_1 > 0.29 && p.gt_stamp_1 < 0.36));
  }
  CHECK(g.pairs.size() == est.size() - 1 - 3);  // est 9 (0.313) and 10 (0.346) are in the gap
  CHECK(g.trans_m.max < 1e-12);
}
