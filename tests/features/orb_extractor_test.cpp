// ORB extractor (ORB-SLAM2 ORBextractor equivalent) on a real TUM frame.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "features/orb_extractor.h"
#include "features/orb_pattern.h"
#include "test_support.h"
#include "io/image_file.h"

using namespace dynref::features;

namespace {
cv::Mat RealGrey() {
  const cv::Mat bgr = dynref::ImageRead(dynref::test::SourcePath(
      "datasets/real/tum_fr1_desk_9frames/rgb/1305031453.359684.png"), cv::IMREAD_COLOR);
  REQUIRE(!bgr.empty());
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  return grey;
}
}  // namespace

TEST_CASE("orb: per-level budget follows ORB-SLAM2's geometric split") {
  OrbExtractor ex(OrbOptions{});
  const auto& n = ex.features_per_level();
  REQUIRE(n.size() == 8);
  int sum = 0;
  for (int v : n) sum += v;
  CHECK(sum == 1000);
  CHECK(n[0] == 217);  // 1000 (1 - 1/1.2) / (1 - 1.2^-8), rounded
  for (size_t i = 1; i + 1 < n.size(); ++i) CHECK(n[i] <= n[i - 1]);
}

TEST_CASE("orb: extraction on a real frame is complete, in budget and deterministic") {
  const cv::Mat grey = RealGrey();
  OrbExtractor ex(OrbOptions{});
  std::vector<cv::KeyPoint> k1, k2;
  cv::Mat d1, d2;
  ex.Extract(grey, &k1, &d1);
  ex.Extract(grey, &k2, &d2);
  CHECK(k1.size() >= 900);
  CHECK(k1.size() <= 1100);
  REQUIRE(d1.rows == static_cast<int>(k1.size()));
  CHECK(d1.cols == 32);
  REQUIRE(k1.size() == k2.size());
  CHECK(cv::norm(d1, d2, cv::NORM_HAMMING) == 0);
  std::vector<int> per_level(8, 0);
  for (size_t i = 0; i < k1.size(); ++i) {
    CHECK(k1[i].pt.x == k2[i].pt.x);
    CHECK(k1[i].angle == k2[i].angle);
    per_level[k1[i].octave]++;
    CHECK(k1[i].pt.x >= 0);
    CHECK(k1[i].pt.x < grey.cols);
    CHECK(k1[i].angle >= 0);
    CHECK(k1[i].angle < 360);
  }
  for (int l = 0; l < 8; ++l) CHECK(per_level[l] <= ex.features_per_level()[l] + 1);
  CHECK(per_level[0] > 150);
}

TEST_CASE("orb: 2, 3 and 4 threads (grid rows, levels, descriptor chunks) give the bytes of 1 (issue 18)") {
  const cv::Mat grey = RealGrey();
  OrbExtractor one(OrbOptions{});
  std::vector<cv::KeyPoint> k1;
  cv::Mat d1;
  one.Extract(grey, &k1, &d1);
  REQUIRE(k1.size() > 900);
  for (int threads : {2, 3, 4}) {
    OrbExtractor ex(OrbOptions{});
    ex.set_threads(threads);
    std::vector<cv::KeyPoint> k;
    cv::Mat d;
    ex.Extract(grey, &k, &d);
    REQUIRE(k.size() == k1.size());
    CHECK(cv::norm(d, d1, cv::NORM_HAMMING) == 0);
    bool same = true;
    for (size_t i = 0; i < k.size(); ++i)
      same = same && k[i].pt == k1[i].pt && k[i].angle == k1[i].angle && k[i].response == k1[i].response &&
             k[i].octave == k1[i].octave && k[i].size == k1[i].size;
    CHECK(same);
  }
}

TEST_CASE("orb: descriptors are rotation invariant (image rotated by 90 degrees)") {
  const cv::Mat grey = RealGrey();
  cv::Mat rot;
  cv::rotate(grey, rot, cv::ROTATE_90_CLOCKWISE);
  OrbExtractor ex(OrbOptions{});
  std::vector<cv::KeyPoint> k1, k2;
  cv::Mat d1, d2;
  ex.Extract(grey, &k1, &d1);
  ex.Extract(rot, &k2, &d2);
  // For level-0 keypoints present in both images (same position after rotation), the
  // descriptors must be close and the angles must differ by ~90 degrees.
  int pairs = 0, close = 0;
  for (size_t i = 0; i < k1.size(); ++i) {
    if (k1[i].octave != 0) continue;
    const cv::Point2f expect(grey.rows - 1 - k1[i].pt.y, k1[i].pt.x);
    for (size_t j = 0; j < k2.size(); ++j) {
      if (k2[j].octave != 0 || cv::norm(k2[j].pt - expect) > 0.5) continue;
      ++pairs;
      if (DescriptorDistance(d1.ptr<uint8_t>(static_cast<int>(i)), d2.ptr<uint8_t>(static_cast<int>(j))) <= 50) ++close;
    }
  }
  REQUIRE(pairs > 50);
  CHECK(close > 0.8 * pairs);
}

TEST_CASE("orb: Hamming distance, rotation bins and the three maxima") {
  uint8_t a[32] = {0}, b[32] = {0};
  CHECK(DescriptorDistance(a, b) == 0);
  b[0] = 0xFF;
  b[31] = 0x01;
  CHECK(DescriptorDistance(a, b) == 9);
  CHECK(RotationBin(10.f, 10.f) == 0);
  CHECK(RotationBin(100.f, 10.f) == 3);   // 90 deg -> round(90 / 30)
  CHECK(RotationBin(10.f, 20.f) == 12);   // -10 -> 350 -> round(11.67)
  std::vector<std::vector<int>> h(kHistoLength);
  h[3] = std::vector<int>(100, 0);
  h[5] = std::vector<int>(20, 0);
  h[7] = std::vector<int>(5, 0);
  int i1, i2, i3;
  ComputeThreeMaxima(h, &i1, &i2, &i3);
  CHECK(i1 == 3);
  CHECK(i2 == 5);
  CHECK(i3 == -1);  // 5 < 10 % of 100
  CHECK(kOrbBitPattern31[0] == 8);
  CHECK(kOrbBitPattern31[3] == 5);
}
