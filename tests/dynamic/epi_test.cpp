// Enhanced-epipolar SLAM (seed 004), Modules A and C: hand-computed stretch, identity and
// fitness of the enhancement, the butterfly optimiser on a known maximum, the relative pose of
// planted 3-D pairs with outliers, the 60 % mask vote, `dynref enhance`, and the method end to end.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dynamic/epi/butterfly.h"
#include "dynamic/epi/enhance.h"
#include "dynamic/epi/enhance_terms.h"
#include "dynamic/epi/mask_vote.h"
#include "geometry/fundamental.h"
#include "geometry/rigid_ransac.h"
#include "method_e2e.h"

using namespace dynref;
using namespace dynref::epi;

TEST_CASE("epi enhance: CDF clipping and stretch, hand-computed") {
  // 100 pixels: 1 at 10, 98 at 100, 1 at 200. s = 0.01: I_lo = 10 (CDF 0.01), I_hi = 100 (CDF 0.99).
  cv::Mat g(10, 10, CV_8U, cv::Scalar(100));
  g.at<uint8_t>(0, 0) = 10;
  g.at<uint8_t>(9, 9) = 200;
  const StretchResult r = CdfStretch(g, 0.01);
  CHECK(r.lo == Approx(10 / 255.0));
  CHECK(r.hi == Approx(100 / 255.0));
  CHECK(r.stretched.at<float>(0, 0) == Approx(0.0f));
  CHECK(r.stretched.at<float>(5, 5) == Approx(1.0f));
  CHECK(r.stretched.at<float>(9, 9) == Approx(1.0f));  // clipped
  // s = 0: I_lo = min{g : CDF(g) >= 0} = 0 literally, I_hi = 200; 100 -> 0.5.
  CHECK(CdfStretch(g, 0.0).lo == 0);
  CHECK(CdfStretch(g, 0.0).stretched.at<float>(5, 5) == Approx(0.5));
  // A constant image is left as it is (I_hi = I_lo).
  CHECK(cv::countNonZero(CdfStretch(cv::Mat(8, 8, CV_8U, cv::Scalar(77)), 0.01).stretched != float(77 / 255.0)) == 0);
}

TEST_CASE("epi enhance: alpha 0 is the identity, alpha > 0 raises local contrast, fitness needs edges") {
  cv::Mat I(60, 80, CV_32F);
  for (int y = 0; y < I.rows; ++y)
    for (int x = 0; x < I.cols; ++x) I.at<float>(y, x) = 0.4f + 0.1f * float((x / 8 + y / 8) % 2);
  EnhanceParams p;
  p.alpha = 0;
  const cv::Mat same = LocalWeightedEnhance(I, p);
  CHECK(cv::norm(same, I, cv::NORM_INF) < 1e-6);
  p.alpha = 1.0, p.p = 1.0;
  const cv::Mat more = LocalWeightedEnhance(I, p);
  double lo, hi, lo0, hi0;
  cv::minMaxLoc(more, &lo, &hi);
  cv::minMaxLoc(I, &lo0, &hi0);
  CHECK(hi - lo > hi0 - lo0);
  CHECK(lo >= 0);
  CHECK(hi <= 1);
  CHECK(std::isinf(EnhancementFitness(cv::Mat(60, 80, CV_32F, cv::Scalar(0.5f)), 0.1)));  // flat: -inf
  CHECK(EnhancementFitness(more, 0.1) > EnhancementFitness(I, 0.1));  // more contrast, more edges
  // --threads (issue 18): rows side by side, the same bytes and the same fitness for 2-4 threads.
  for (int threads : {2, 3, 4}) {
    CHECK(cv::norm(LocalWeightedEnhance(I, p, threads), more, cv::NORM_INF) == 0);
    CHECK(EnhancementFitness(more, 0.1, threads) == EnhancementFitness(more, 0.1));
  }
}

TEST_CASE("epi enhance: the BOA's precomputed terms and reused buffers give the same bytes") {
  // Noisy texture with saturated corners (the clamp decided without pow) and flat patches (repeated ratios).
  cv::Mat g(90, 120, CV_8U);
  Rng rng(7, "epi-terms");
  for (int y = 0; y < g.rows; ++y)
    for (int x = 0; x < g.cols; ++x)
      g.at<uint8_t>(y, x) = uint8_t(x < 10 ? 0 : x > 110 ? 255 : y < 20 ? 128 : 40 + (x * 7 + y * 3) % 150 + int(rng.Uniform01() * 20));
  const cv::Mat st = CdfStretch(g, 0.01).stretched;
  EnhanceParams p;
  EnhanceTerms terms(st, p), terms2(st, p, 3);
  CHECK(terms.distinct_ratios() < st.total());
  EnhanceWorkspace ws;
  cv::Mat out, out2, out3;
  for (const auto& [alpha, e] : std::vector<std::pair<double, double>>{{0.0, 1.0}, {2.0, 0.25}, {0.37, 3.0}, {1.1, 1.7}}) {
    p.alpha = alpha, p.p = e;
    const cv::Mat ref = LocalWeightedEnhance(st, p);
    terms.Apply(alpha, e, out);
    terms2.Apply(alpha, e, out2, 3);
    LocalWeightedEnhance(st, p, 1, ws, out3);
    CHECK(cv::norm(out, ref, cv::NORM_INF) == 0);
    CHECK(std::memcmp(out.data, ref.data, ref.total() * sizeof(float)) == 0);
    CHECK(std::memcmp(out2.data, ref.data, ref.total() * sizeof(float)) == 0);
    CHECK(std::memcmp(out3.data, ref.data, ref.total() * sizeof(float)) == 0);
    FitnessTerms a, b;
    const double fa = EnhancementFitness(ref, 0.1, 1, &a), fb = EnhancementFitness(ref, 0.1, 1, &b, ws);
    CHECK(std::memcmp(&fa, &fb, sizeof(double)) == 0);
    CHECK(a.sobel_sum == b.sobel_sum);
    CHECK(a.entropy == b.entropy);
  }
  EnhanceBuffers buffers;
  for (int i = 0; i < 2; ++i) {  // the second call reuses every buffer
    const EnhanceResult fresh = Enhance(g, p), reused = Enhance(g, p, 1, buffers);
    CHECK(std::memcmp(fresh.grey8.data, reused.grey8.data, fresh.grey8.total()) == 0);
    CHECK(fresh.fitness == reused.fitness);
  }
}

TEST_CASE("epi butterfly optimisation: finds a known maximum, deterministic per seed") {
  const Fitness f = [](const std::vector<double>& x) {
    return -(x[0] - 0.3) * (x[0] - 0.3) - (x[1] - 1.7) * (x[1] - 1.7);
  };
  BoaOptions o;
  Rng a(5, "boa"), b(5, "boa");
  const BoaResult r = ButterflyOptimise(f, {0, 0.25}, {2, 3}, o, a);
  CHECK(r.evaluations == 20 + 20 * 30);
  CHECK(r.best[0] == Approx(0.3).margin(0.05));
  CHECK(r.best[1] == Approx(1.7).margin(0.05));
  for (size_t i = 1; i < r.best_per_iteration.size(); ++i) CHECK(r.best_per_iteration[i] >= r.best_per_iteration[i - 1]);
  const BoaResult r2 = ButterflyOptimise(f, {0, 0.25}, {2, 3}, o, b);
  CHECK(r2.best == r.best);
  CHECK_THROWS(ButterflyOptimise(f, {1, 0}, {0, 1}, o, a));
}

TEST_CASE("epi relative pose: planted rotation and translation recovered through 30 % outliers") {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.03, -0.01, 0.02);
  const double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;
  std::vector<geometry::PointPair3D> pairs;
  Rng g(2, "points");
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d X(g.Uniform(-1, 1), g.Uniform(-0.8, 0.8), g.Uniform(1, 4));
    Eigen::Vector3d Y = R * X + t;
    if (i % 10 < 3) Y += Eigen::Vector3d(g.Uniform(0.1, 0.3), g.Uniform(-0.3, -0.1), 0);  // a moving object
    pairs.push_back({X, Y, {fx * Y.x() / Y.z() + cx, fy * Y.y() / Y.z() + cy}});
  }
  Rng rng(1, "epi.pose");
  const geometry::RigidRansacResult r = geometry::RigidRansac(pairs, fx, fy, cx, cy, geometry::RigidRansacOptions{}, rng);
  REQUIRE(r.valid);
  CHECK(r.inlier_count == 70);
  CHECK((r.R - R).norm() < 1e-9);
  CHECK((r.t - t).norm() < 1e-9);
  for (int i = 0; i < 100; ++i) CHECK(bool(r.inliers[size_t(i)]) == (i % 10 >= 3));
  // Too few pairs: no pose.
  Rng rng2(1, "epi.pose");
  CHECK_FALSE(geometry::RigidRansac({pairs.begin(), pairs.begin() + 5}, fx, fy, cx, cy, {}, rng2).valid);
}

TEST_CASE("epi mask vote: more than 60 % violating is dynamic, exactly 60 % is not, no match is dynamic") {
  const double nan = std::nan("");
  // Mask 1: 5 matched, 3 violate (60 %: static). Mask 2: 5 matched, 4 violate (dynamic). Mask 3:
  // keypoints without matches (dynamic, E8). Mask 4: no keypoint at all (dynamic). 0 = static region.
  const std::vector<int> inst = {1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 3, 3, 0, 0};
  const std::vector<double> d = {2, 3, 4, 0.5, 0.2, 2, 2, 2, 2, 0.1, nan, nan, 9, 9};
  const auto v = VoteMasks(inst, d, {1, 2, 3, 4}, MaskVoteOptions{});
  REQUIRE(v.size() == 4);
  CHECK(v.at(1).matched == 5);
  CHECK(v.at(1).violating == 3);
  CHECK_FALSE(v.at(1).dynamic);
  CHECK(v.at(2).dynamic);
  CHECK(v.at(2).ratio == Approx(0.8));
  CHECK(v.at(3).matched == 0);
  CHECK(v.at(3).dynamic);
  CHECK(v.at(4).dynamic);
}

// Issue 38: a still camera (t = 0) has no fundamental matrix; the old distance was +inf, so every
// tracked in-mask keypoint of such a frame "violated" and every mask with a match was dynamic.
TEST_CASE("epi vote distance: t = 0 takes the rotation-only limit, t != 0 is Eq. (14)") {
  Eigen::Matrix3d K;
  K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector2d p(100, 200);
  const Eigen::Vector2d Hp = (K * R * K.inverse() * p.homogeneous()).hnormalized();
  // Still camera, rotating: a static point lands on H p (distance 0), one 3 px off it is 3 px away.
  CHECK(VoteDistance(K, R, Eigen::Vector3d::Zero(), p, Hp) == Approx(0).margin(1e-9));
  CHECK(VoteDistance(K, R, Eigen::Vector3d::Zero(), p, Hp + Eigen::Vector2d(0, 3)) == Approx(3));
  const std::vector<double> d = {VoteDistance(K, R, Eigen::Vector3d::Zero(), p, Hp),
                                 VoteDistance(K, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), p, p)};
  CHECK_FALSE(VoteMasks({1, 1}, d, {1}, MaskVoteOptions{}).at(1).dynamic);  // was: 2 of 2 violating
  // Moving camera: the point-to-line distance of Eq. (14).
  const Eigen::Vector3d t(0.1, 0, 0);
  const Eigen::Vector2d q(150, 260);
  CHECK(VoteDistance(K, R, t, p, q) ==
        Approx(geometry::EpipolarDistance(geometry::FundamentalFromPose(K, R, t), p, q)));
}

TEST_CASE("epi end to end: dynref enhance, and A + C on a low-light walking sequence", "[cli]") {
  const std::string dir = test::ScratchDir("epi_e2e");
  synth::SynthOptions so;
  so.preset = "walking_xyz", so.frames = 60, so.seed = 3, so.low_light = true, so.detections = "yolo-like";
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  test::E2eSequence seq{so, so.out + "/detections/yolo-like"};
  const double epi_c = test::RunE2eAte(seq, "epi_C", dir + "/c");
  const double epi = test::RunE2eAte(seq, "epi", dir + "/epi");
  INFO("ATE C " << epi_c << " A+C " << epi);
  CHECK(epi < 0.03);
  CHECK(epi_c < 0.1);
  // dynref enhance on the sequence: one PNG per frame and the parameters the stage would use.
  const test::CommandResult r = test::RunDynref("enhance " + so.out + " --out " + dir + "/enh");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::ifstream log(dir + "/enh/enhance.txt");
  std::string line;
  int images = 0;
  while (std::getline(log, line)) images += line.find(".png ") != std::string::npos;
  CHECK(images == 60);
  // Refuses to overwrite a folder it did not write.
  std::filesystem::create_directories(dir + "/other");
  test::WriteText(dir + "/other/x.txt", "x\n");
  const test::CommandResult bad = test::RunDynref("enhance " + so.out + " --out " + dir + "/other");
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("not written by dynref enhance") != std::string::npos);
}

