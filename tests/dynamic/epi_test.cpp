// Enhanced-epipolar SLAM (seed 004), Modules A and C: hand-computed stretch, identity and
// fitness of the enhancement, the butterfly optimiser on a known maximum, the relative pose of
// planted 3-D pairs with outliers, the 60 % mask vote, `dynref enhance`, and the method end to end.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dynamic/epi/butterfly.h"
#include "dynamic/epi/enhance.h"
#include "dynamic/epi/mask_vote.h"
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

TEST_CASE("epi end to end: dynref enhance, and A + C on a low-light walking sequence") {
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

TEST_CASE("epi reproduce: epi-table2 end to end on 10 frames, paper rows beside ours") {
  const std::string dir = test::ScratchDir("epi_reproduce");
  const test::CommandResult bad = test::RunDynref("reproduce epi-table2 --frames 10 --gap 10 --work " + dir + "/w --out " + dir + "/t2.md");
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("--gap") != std::string::npos);
  CHECK_FALSE(test::FileExists(dir + "/w"));
  const test::CommandResult r =
      test::RunDynref("reproduce epi-table2 --frames 10 --seeds 1 --work " + dir + "/w --out " + dir + "/t2.md");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::ifstream in(dir + "/t2.md");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string md = ss.str();
  CHECK(md.find("| Light change | ORB + MNN2 | 1 |") != std::string::npos);  // one pair (0, 5) per sequence
  CHECK(md.find("| Low light (both frames dark) | SIFT + BF |") != std::string::npos);
  // The distance distributions the backbone's SIFT gates are read from (issue 17).
  CHECK(md.find("| SIFT correct | ") != std::string::npos);
  CHECK(md.find("| SIFT wrong | ") != std::string::npos);
  CHECK(md.find("| ORB wrong | ") != std::string::npos);
  CHECK(md.find("| Light change | Zippypoint + MNN2 | 295 | 83.10 | 0.245 |") != std::string::npos);  // paper row
  CHECK(md.find("| Low-texture environments | ORB + BF | 0 | 0.00 | 0.719 |") != std::string::npos);
}

TEST_CASE("epi reproduce: epi-table3 end to end on 30 frames (ATE, ablation, mask vote, time), bad arguments first") {
  const std::string dir = test::ScratchDir("epi_reproduce_t3");
  const test::CommandResult bad = test::RunDynref("reproduce epi-table3 --frames 30 --sequences walking_static "
                                                  "--ablation-sequences crowd --work " + dir + "/w --out " + dir + "/t3.md");
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("--ablation-sequences") != std::string::npos);
  CHECK_FALSE(test::FileExists(dir + "/w"));
  const test::CommandResult r = test::RunDynref(
      "reproduce epi-table3 --frames 30 --seeds 1 --sequences walking_static --ablation-sequences walking_static "
      "--timing-sequence walking_static --work " + dir + "/w --out " + dir + "/t3.md");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string md = test::ReadFileBytes(dir + "/t3.md");
  INFO(md);
  // Paper values beside ours: Table 3 (w_static RMSE 0.0078), Table 6 (None 0.4094 ... ALL 0.0078).
  CHECK(md.find("| walking_static | normal light |") != std::string::npos);
  CHECK(md.find("| 0.0069 | 0.0063 | 0.0078 | 0.0036 |") != std::string::npos);
  CHECK(md.find("| 0.4094 | 0.3463 | 0.3397 | 0.0097 | 0.0084 | 0.0081 | 0.0078 |") != std::string::npos);
  // Module C decided on masks in every frame after the first; the table counts them.
  const size_t at = md.find("| walking_static | normal light | epi | ");
  REQUIRE(at != std::string::npos);
  CHECK(std::stoi(md.substr(at + std::string("| walking_static | normal light | epi | ").size())) > 20);
  CHECK(md.find("| OURS | RTX 4060 Ti | 41.9–58.4 |") != std::string::npos);  // Table 7 as printed
  // Module B (issue 17): the B, B + C and ALL columns ran, ALL voted on masks and was timed.
  CHECK(md.find("B (epi_B) | C (epi_C) | A + C (epi) | B + C (epi_BC) | ALL (epi_ALL) |") != std::string::npos);
  const size_t all = md.find("| walking_static | normal light | epi_ALL | ");
  REQUIRE(all != std::string::npos);
  CHECK(std::stoi(md.substr(all + std::string("| walking_static | normal light | epi_ALL | ").size())) > 20);
  CHECK(md.find("| epi_ALL | normal light | ") != std::string::npos);
  // Every dynref column of the Table 6 row has a value ("-" = no ATE).
  const size_t t6 = md.find("| walking_static | normal light |", md.find("## Module ablation"));
  REQUIRE(t6 != std::string::npos);
  std::string row = md.substr(t6, md.find('\n', t6) - t6);
  std::vector<std::string> cells;
  for (size_t b = 1, e; (e = row.find('|', b)) != std::string::npos; b = e + 1) cells.push_back(row.substr(b, e - b));
  REQUIRE(cells.size() >= 9);
  for (size_t c = 2; c < 9; ++c) CHECK(cells[c] != " - ");
}
