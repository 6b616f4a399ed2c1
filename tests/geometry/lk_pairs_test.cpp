#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "core/rng.h"
#include "geometry/lk_pairs.h"

using namespace dynref::geometry;

namespace {
// Smooth random texture (deterministic).
cv::Mat Texture(int w, int h) {
  dynref::Rng rng(3, "test.texture");
  cv::Mat noise(h, w, CV_32F);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) noise.at<float>(y, x) = static_cast<float>(rng.Uniform(0, 255));
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 2.0);
  cv::Mat out;
  cv::normalize(noise, noise, 0, 255, cv::NORM_MINMAX);
  noise.convertTo(out, CV_8U);
  return out;
}
}  // namespace

TEST_CASE("lk pairs: backward tracking recovers a known shift") {
  const cv::Mat prev = Texture(160, 120);
  cv::Mat cur;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 3, 0, 1, 2);  // cur(x) = prev(x - d)
  cv::warpAffine(prev, cur, shift, prev.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  std::vector<cv::Point2f> pts = {{40, 40}, {80, 60}, {120, 90}, {60.5f, 70.25f}};
  const std::vector<LkPair> pairs = TrackBackward(prev, cur, pts, LkOptions{});
  REQUIRE(pairs.size() == 4);
  for (const auto& p : pairs) {
    REQUIRE(p.tracked);
    CHECK(p.p_prev.x == Approx(p.p_cur.x - 3).margin(0.05));
    CHECK(p.p_prev.y == Approx(p.p_cur.y - 2).margin(0.05));
  }
  // Determinism: same call, same floats.
  const std::vector<LkPair> again = TrackBackward(prev, cur, pts, LkOptions{});
  for (size_t i = 0; i < pairs.size(); ++i) CHECK(again[i].p_prev == pairs[i].p_prev);
}

TEST_CASE("lk pairs: the same pairs for any thread count (slices of points side by side)") {
  const cv::Mat prev = Texture(320, 240);
  cv::Mat cur;
  const cv::Mat warp = (cv::Mat_<double>(2, 3) << 1.01, 0.02, 2.5, -0.01, 0.99, 1.5);
  cv::warpAffine(prev, cur, warp, prev.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  std::vector<cv::Point2f> pts;
  for (int i = 0; i < 300; ++i) pts.emplace_back(5.f + static_cast<float>((i * 37) % 310), 5.f + static_cast<float>((i * 53) % 230));
  LkOptions one;
  const std::vector<LkPair> ref = TrackBackward(prev, cur, pts, one);
  int tracked = 0;
  for (const LkPair& p : ref) tracked += p.tracked;
  CHECK(tracked > 250);
  for (int threads : {2, 3, 4}) {
    LkOptions o;
    o.threads = threads;
    const std::vector<LkPair> got = TrackBackward(prev, cur, pts, o);
    REQUIRE(got.size() == ref.size());
    for (size_t i = 0; i < ref.size(); ++i) {
      CHECK(got[i].p_prev == ref[i].p_prev);
      CHECK(got[i].tracked == ref[i].tracked);
    }
  }
  LkOptions bad;
  bad.threads = 0;
  CHECK_THROWS_AS(TrackBackward(prev, cur, pts, bad), std::invalid_argument);
}

TEST_CASE("lk pairs: pruning by border, patch SAD and mask") {
  const cv::Mat prev = Texture(100, 80);
  const cv::Mat cur = prev.clone();
  LkOptions o;
  LkPair p;
  p.tracked = true;
  p.p_prev = p.p_cur = {50, 40};
  PrunePair(prev, cur, false, o, p);
  CHECK(p.prune_reason.empty());
  CHECK(p.patch_sad == 0);
  CHECK(p.usable_for_F());
  PrunePair(prev, cur, true, o, p);
  CHECK(p.prune_reason == "in-mask");
  CHECK(!p.usable_for_F());
  p.p_cur = {3, 40};
  PrunePair(prev, cur, false, o, p);
  CHECK(p.prune_reason == "border");
  p.p_cur = {95, 40};  // x >= cols - b
  PrunePair(prev, cur, false, o, p);
  CHECK(p.prune_reason == "border");
  cv::Mat bright = prev.clone();
  bright(cv::Rect(45, 35, 10, 10)).setTo(255);
  cv::Mat dark = prev.clone();
  dark(cv::Rect(45, 35, 10, 10)).setTo(0);
  p.p_prev = p.p_cur = {50, 40};
  PrunePair(dark, bright, false, o, p);
  CHECK(p.patch_sad == 9 * 255);
  CHECK(p.prune_reason == "patch-sad");
  LkPair failed;
  PrunePair(prev, cur, false, o, failed);
  CHECK(failed.prune_reason == "lk-failed");
}
