// Motion-blur SLAM (seed 003): hand-computed checks of the line fit (raw Unix timestamps
// included), the compensation trigger and paste, the human value range, the k-d tree probability
// of a planted cluster, and the method end to end on a blurred synthetic walking sequence.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>

#include "dynamic/blur/compensation.h"
#include "dynamic/blur/depth_fusion.h"
#include "dynamic/blur/keypoint_probability.h"
#include "io/mask_layers.h"
#include "method_e2e.h"

using namespace dynref;
using namespace dynref::blur;

TEST_CASE("blur: corner line fit, hand-computed, at raw Unix timestamps") {
  // x = 100 + 30 (t - t0) px/s, y = 50 - 6 (t - t0): exact line, prediction at t0 + 0.1.
  const double t0 = 1305031102.175304;  // TUM fr3 walking_xyz first stamp
  std::vector<CornerSample> h;
  for (int j = 0; j < 3; ++j) {
    const double dt = 0.0333 * j;
    h.push_back({100 + 30 * dt, 50 - 6 * dt, t0 + dt});
  }
  const cv::Point2d p = PredictCorner(h, t0 + 0.1);
  CHECK(p.x == Approx(103.0).margin(1e-6));
  CHECK(p.y == Approx(49.4).margin(1e-6));
  // The naive closed form on absolute time cancels catastrophically: n*sum(t^2) - sum(t)^2 for
  // three stamps ~1.3e9 s apart by 33 ms is ~0.0067 s^2 computed from two ~5e18 numbers whose
  // spacing at that magnitude is ~1e3, i.e. pure rounding noise.
  double st = 0, stt = 0;
  for (const auto& s : h) st += s.t, stt += s.t * s.t;
  const double naive_den = 3 * stt - st * st;  // exact value: 3 * 0.0333^2 * 2 = 0.00665334
  CHECK(std::abs(naive_den - 0.00665334) > 1.0);  // the naive denominator is garbage
  // Noisy samples: least squares, hand-computed. tau = -2, -1, 0 (t_c = 2): x = 10, 12, 15.
  // k = (3*(-20-12) - 37*(-3)) / (3*5 - 9) = 15/6 = 2.5, b = (37 - 2.5*(-3))/3 = 44.5/3.
  const std::vector<CornerSample> noisy = {{10, 0, 0}, {12, 0, 1}, {15, 0, 2}};
  CHECK(PredictCorner(noisy, 2).x == Approx(44.5 / 3));
  // Two entries: the line through them; one: copied in place.
  CHECK(PredictCorner({{0, 0, 0}, {4, 2, 1}}, 2).x == Approx(8));
  CHECK(PredictCorner({{0, 0, 0}, {4, 2, 1}}, 2).y == Approx(4));
  CHECK(PredictCorner({{7, 9, 5}}, 6) == cv::Point2d(7, 9));
}

namespace {

PersonMask Box(int x, int y, int w, int h, int id = 1) {
  PersonMask p;
  p.detection_id = id;
  p.mask = cv::Mat::zeros(480, 640, CV_8U);
  p.mask(cv::Rect(x, y, w, h)).setTo(255);
  p.box = cv::Rect(x, y, w, h);
  return p;
}

}  // namespace

TEST_CASE("blur: a person the segmenter drops is pasted at the line-fit prediction") {
  MissedSegmentationCompensator c(CompensationOptions{}, cv::Size(640, 480));
  // Person A walks right 10 px/frame; person B stands. Frame 3 misses A.
  for (int i = 0; i < 3; ++i) {
    const auto r = c.Process(0.1 * i, {Box(100 + 10 * i, 100, 50, 100, 1), Box(400, 100, 50, 100, 2)});
    CHECK(r.pasted.empty());
    if (i > 0) CHECK(r.r == Approx(1.0));
  }
  const auto r = c.Process(0.3, {Box(400, 100, 50, 100, 1)});
  CHECK(r.r == Approx(0.5));  // one of two equal persons left
  REQUIRE(r.triggered);
  REQUIRE(r.pasted.size() == 1);
  CHECK(r.pasted[0].samples == 3);
  CHECK(r.pasted[0].from == cv::Point2d(120, 100));
  CHECK(r.pasted[0].to.x == Approx(130));
  CHECK(r.pasted[0].to.y == Approx(100));
  CHECK(r.pasted[0].pasted_px == 5000);
  CHECK(cv::countNonZero(r.mask(cv::Rect(130, 100, 50, 100))) == 5000);
  CHECK(cv::countNonZero(r.mask) == 10000);
  // Disabled (ablation "w/o compensation"): same input, nothing pasted.
  MissedSegmentationCompensator off(CompensationOptions{}, cv::Size(640, 480));
  for (int i = 0; i < 3; ++i) off.Process(0.1 * i, {Box(100 + 10 * i, 100, 50, 100, 1), Box(400, 100, 50, 100, 2)}, false);
  CHECK(off.Process(0.3, {Box(400, 100, 50, 100, 1)}, false).pasted.empty());
}

TEST_CASE("blur: a person who left is predicted at most max_consecutive frames, and not when r >= 0.9") {
  CompensationOptions o;
  o.max_consecutive = 2;
  MissedSegmentationCompensator c(o, cv::Size(640, 480));
  c.Process(0.0, {Box(100, 100, 50, 100)});
  CHECK(c.Process(0.1, {}).pasted.size() == 1);   // A_(c-1) = 5000, A_c = 0: r = 0
  CHECK(c.Process(0.2, {}).pasted.size() == 1);
  CHECK(c.Process(0.3, {}).pasted.empty());       // third frame in a row: dropped
  CHECK(c.Process(0.4, {}).r == -1);              // A_(c-1) = 0: r undefined (E1)
  // A second person of equal size appears while the first is missed: r = 1, no compensation.
  MissedSegmentationCompensator d(CompensationOptions{}, cv::Size(640, 480));
  d.Process(0.0, {Box(100, 100, 50, 100)});
  const auto r = d.Process(0.1, {Box(400, 100, 50, 100)});
  CHECK(r.r == Approx(1.0));
  CHECK_FALSE(r.triggered);
}

// Issue 38: a paste clipped at the image edge keeps the unclipped corner it was moved to; the
// next paste moves the mask by the fitted velocity from there. Translating from the clipped box
// (x = 0) moved it 20 px too far each frame and dropped a person still 10 px in view.
TEST_CASE("blur: a person leaving the image is pasted at the fitted velocity, also after a clipped paste") {
  MissedSegmentationCompensator c(CompensationOptions{}, cv::Size(640, 480));
  for (int i = 0; i < 3; ++i) c.Process(0.1 * i, {Box(60 - 20 * i, 100, 50, 100)});  // x = 60, 40, 20
  const auto r3 = c.Process(0.3, {});  // missed: predicted x = 0, whole mask in the image
  REQUIRE(r3.pasted.size() == 1);
  CHECK(r3.pasted[0].shift == cv::Point(-20, 0));
  CHECK(r3.pasted[0].box == cv::Rect(0, 100, 50, 100));
  const auto r4 = c.Process(0.4, {});  // predicted x = -20: clipped to x 0..29
  REQUIRE(r4.pasted.size() == 1);
  CHECK(r4.pasted[0].from == cv::Point2d(0, 100));
  CHECK(r4.pasted[0].shift == cv::Point(-20, 0));
  CHECK(r4.pasted[0].box == cv::Rect(0, 100, 30, 100));
  const auto r5 = c.Process(0.5, {});  // predicted x = -40: 10 px still in view
  REQUIRE(r5.pasted.size() == 1);
  CHECK(r5.pasted[0].from == cv::Point2d(-20, 100));  // the anchor, not the clipped box's x = 0
  CHECK(r5.pasted[0].to.x == Approx(-40));
  CHECK(r5.pasted[0].shift == cv::Point(-20, 0));
  CHECK(r5.pasted[0].box == cv::Rect(0, 100, 10, 100));
  CHECK(r5.pasted[0].moved_px == 1000);
  CHECK(r5.dropped.empty());
}

TEST_CASE("blur: human value range and 3-sigma screen, hand-computed") {
  // Box 100x100 at (200, 100): left half a person at 1.5 m, right half a wall at 3.0 m.
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(4.0f));
  depth(cv::Rect(200, 100, 50, 100)).setTo(1.5f);
  depth(cv::Rect(250, 100, 50, 100)).setTo(3.0f);
  depth.at<float>(150, 220) = 0;  // a hole: never sampled, never fused
  DepthFusionOptions o;
  o.alpha_m = 0.3;
  // Samples: three on the person, one on the wall, one outside the box, one on the hole.
  const std::vector<cv::Point> samples = {{210, 110}, {230, 150}, {240, 190}, {280, 150}, {50, 50}, {220, 150}};
  cv::Mat fused = cv::Mat::zeros(480, 640, CV_8U);
  const HumanValueRange h = FuseBoxDepth(depth, cv::Rect(200, 100, 100, 100), samples, o, &fused);
  CHECK(h.samples == 4);
  CHECK(h.g_h == Approx((1.5 * 3 + 3.0) / 4));  // 1.875: biased by the wall sample (E6)
  CHECK(h.lo == Approx(1.575));
  CHECK(h.hi == Approx(2.175));
  CHECK(h.box_valid_px == 9999);
  // mu = (4999 * 1.5 + 5000 * 3) / 9999; sigma ~0.75, 3 sigma = 2.25: nothing screened here.
  CHECK(h.mu_box == Approx((4999 * 1.5 + 5000 * 3.0) / 9999));
  // 1.5 is outside [1.575, 2.175]: the biased mean misses the person entirely, as the paper's
  // reading predicts when the box holds much background.
  CHECK(h.fused_px == 0);
  // alpha 0.5 covers 1.5: every valid person pixel joins, the wall does not.
  o.alpha_m = 0.5;
  const HumanValueRange h2 = FuseBoxDepth(depth, cv::Rect(200, 100, 100, 100), samples, o, &fused);
  CHECK(h2.fused_px == 4999);
  CHECK(cv::countNonZero(fused) == 4999);
  CHECK(fused.at<uint8_t>(150, 220) == 0);
  // 3-sigma screen: a uniform box with one far outlier inside the range is cut by a tight screen.
  o.sigma_mult = 0.1;
  cv::Mat fused3 = cv::Mat::zeros(480, 640, CV_8U);
  CHECK(FuseBoxDepth(depth, cv::Rect(200, 100, 100, 100), samples, o, &fused3).fused_px == 0);
  // Stratified samples: one per cell, inside its cell, deterministic per seed.
  Rng a(3, "x"), b(3, "x");
  const auto sa = StratifiedSamples(cv::Size(640, 480), DepthFusionOptions{}, a);
  REQUIRE(sa.size() == 192);
  CHECK(sa == StratifiedSamples(cv::Size(640, 480), DepthFusionOptions{}, b));
  for (size_t i = 0; i < sa.size(); ++i) {
    CHECK(sa[i].x / 40 == int(i % 16));
    CHECK(sa[i].y / 40 == int(i / 16));
  }
}

// Issue 38: the screen at the paper's own 3 sigma. Box rows: 49 at 1.9 m, 49 at 2.1 m, one at
// 2.30 m, one at 2.34 m: mu = 2.0064, sigma = 0.10870 (python3), so 2.30 m is 2.70 sigma from mu
// (kept) and 2.34 m is 3.07 sigma (cut); O_h = [1.5, 2.5] holds all four. A screen at 2.5 sigma
// or at 3.5 sigma (planted: both seen failing) moves 100 pixels.
TEST_CASE("blur: the 3-sigma screen keeps a row at 2.70 sigma and cuts one at 3.07 sigma") {
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(4.0f));
  const cv::Rect box(200, 100, 100, 100);
  depth(cv::Rect(200, 100, 100, 49)).setTo(1.9f);
  depth(cv::Rect(200, 149, 100, 49)).setTo(2.1f);
  depth(cv::Rect(200, 198, 100, 1)).setTo(2.30f);
  depth(cv::Rect(200, 199, 100, 1)).setTo(2.34f);
  DepthFusionOptions o;  // sigma_mult 3 (paper)
  o.alpha_m = 0.5;
  const std::vector<cv::Point> samples = {{210, 110}, {210, 160}};  // 1.9 and 2.1: g_h = 2.0
  cv::Mat fused = cv::Mat::zeros(480, 640, CV_8U);
  const HumanValueRange h = FuseBoxDepth(depth, box, samples, o, &fused);
  CHECK(h.mu_box == Approx(2.0064).epsilon(1e-6));
  CHECK(h.sigma_box == Approx(0.10869701007847464).epsilon(1e-5));
  CHECK(h.fused_px == 9900);
  CHECK(fused.at<uint8_t>(198, 250) == 255);
  CHECK(fused.at<uint8_t>(199, 250) == 0);
}

TEST_CASE("blur: k-d tree probability of a planted cluster, hand-computed") {
  // Keypoint 0 static at the origin; 1 and 2 in the mask at 10 px and 20 px (outside D = 20,
  // strict); 3 static at 5 px; 4 far away, alone.
  const std::vector<cv::Point2f> pts = {{100, 100}, {110, 100}, {100, 120}, {103, 104}, {400, 400}};
  const std::vector<uint8_t> mask = {0, 1, 1, 0, 0};
  KeypointProbabilityOptions o;  // D 20, c1 1, c2 0.05, theta 0.5
  const auto p = KeypointProbabilities(pts, mask, o);
  // 0: neighbours 1 (10 px, P 1) and 3 (5 px, P 0); 2 at exactly 20 px is out. P' = e^-0.5 / 2.
  CHECK(p[0].neighbours == 2);
  CHECK(p[0].dynamic_neighbours == 1);
  CHECK(p[0].post == Approx(std::exp(-0.5) / 2));
  CHECK_FALSE(p[0].dynamic);
  // 3: neighbours 0 (5), 1 (|(7,-4)| = 8.062), 2 (|(-3,16)| = 16.279); P' = (e^-0.403 + e^-0.814)/3.
  CHECK(p[3].neighbours == 3);
  CHECK(p[3].post == Approx((std::exp(-0.05 * std::sqrt(65.0)) + std::exp(-0.05 * std::sqrt(265.0))) / 3));
  CHECK_FALSE(p[3].dynamic);  // 0.3377 < 0.5
  CHECK(p[1].post == 1);
  CHECK(p[1].dynamic);
  CHECK(p[4].neighbours == 0);
  CHECK(p[4].post == 0);
  // theta 0.3 makes keypoint 3 dynamic, c1 = 2 makes 0 dynamic too (2 * 0.303 = 0.607).
  o.theta = 0.3;
  CHECK(KeypointProbabilities(pts, mask, o)[3].dynamic);
  o.theta = 0.5, o.c1 = 2;
  CHECK(KeypointProbabilities(pts, mask, o)[0].dynamic);
  // "w/o probability": dynamic iff in the mask.
  o.compute = false;
  const auto q = KeypointProbabilities(pts, mask, o);
  for (size_t i = 0; i < pts.size(); ++i) CHECK(q[i].dynamic == bool(mask[i]));
}

TEST_CASE("blur end to end: blurred walking sequence, people rejected, ATE far below orb's", "[e2e][cli]") {
  const std::string dir = test::ScratchDir("blur_e2e");
  const test::E2eSequence seq = test::MakeE2eSequence(dir, 60, 3, "sparseinst-like", true);
  const double orb = test::RunE2eAte(seq, "orb", dir + "/orb");
  const double blur = test::RunE2eAte(seq, "blur", dir + "/blur");
  INFO("ATE orb " << orb << " blur " << blur);
  CHECK(blur < 0.05);
  CHECK(blur < 0.5 * orb);
  // configs/blur.yaml writes the origin of every mask pixel (dynref overlay colours it) and
  // run.json times each stage (Table 4).
  const MaskLayersReader layers(dir + "/blur/masks");
  REQUIRE(layers.legend().size() == 4);
  CHECK(layers.legend()[1].name == "compensation");
  std::ifstream in(dir + "/blur/run.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  CHECK(j["timing_stages"].contains("blur.mask"));
  CHECK(j["timing_stages"]["blur.probability"].get<double>() > 0);
  // Sec. 4.4 / spec 003 step 7 (issue 38): the dense static map of the keyframe pixels outside
  // M_sd, scored against the scene's truth by map-eval (ghosts: points near a mover). Measured:
  // 1.79 % ghosts, 88.9 % complete; planted: the module ignoring the mask -> 13.91 % ghosts, fails.
  const test::CommandResult me = test::RunDynref("map-eval " + test::Quote(dir + "/blur/dense_map.ply") + " --gt " +
                                                 test::Quote(seq.synth.out) + " --json " + test::Quote(dir + "/map_eval.json"));
  INFO(me.output);
  REQUIRE(me.exit_code == 0);
  const nlohmann::json m = nlohmann::json::parse(test::ReadFileBytes(dir + "/map_eval.json"));
  CHECK(m["map_points"].get<int64_t>() > 100000);
  CHECK(m["completeness"].get<double>() > 0.5);
  CHECK(m["ghost_fraction"].get<double>() < 0.05);
}

