// The feature plug-in point (issue 17, Module B): descriptor distances for both descriptor kinds,
// OpenCV SIFT behind the interface, and the SuperPoint-style ONNX path decoded exactly on a
// model the test writes itself (tiny_onnx_model.h).
#include <catch2/catch.hpp>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/rng.h"
#include "features/keypoint_extractor.h"
#include "features/mnn2.h"
#include "features/onnx_extractor.h"
#include "features/sift_extractor.h"
#include "test_support.h"
#include "tiny_onnx_model.h"

using namespace dynref;
using namespace dynref::features;

namespace {

// Textured grey image: smoothed seeded noise plus a few shapes.
cv::Mat Texture(uint64_t seed, int w = 640, int h = 480) {
  Rng rng(seed, "plugin-test");
  cv::Mat small(h / 8, w / 8, CV_8U);
  for (int y = 0; y < small.rows; ++y)
    for (int x = 0; x < small.cols; ++x) small.at<uint8_t>(y, x) = static_cast<uint8_t>(rng.UniformInt(0, 255));
  cv::Mat img;
  cv::resize(small, img, cv::Size(w, h), 0, 0, cv::INTER_CUBIC);
  cv::rectangle(img, cv::Rect(100, 100, 80, 60), cv::Scalar(255), -1);
  cv::circle(img, cv::Point(400, 300), 40, cv::Scalar(0), -1);
  return img;
}

// 4 x 4 blob of a 1 x C x H x W float blob, zero-filled.
cv::Mat Blob(int c, int h, int w) {
  const int sz[4] = {1, c, h, w};
  return cv::Mat(4, sz, CV_32F, cv::Scalar(0));
}
float& BlobAt(cv::Mat& b, int c, int y, int x) { return b.ptr<float>(0, c)[static_cast<size_t>(y) * b.size[3] + x]; }

}  // namespace

TEST_CASE("plugin: row distances are Hamming bits for binary rows and squared L2 for float rows") {
  Rng rng(3, "plugin-bits");
  cv::Mat a(2, 32, CV_8U), f(2, 256, CV_32F);
  for (int r = 0; r < 2; ++r)
    for (int k = 0; k < 32; ++k) a.at<uint8_t>(r, k) = static_cast<uint8_t>(rng.UniformInt(0, 255));
  // +-1/16 coding of the same bits: squared L2 = 4 * Hamming / 256 (spec 004 step 3).
  for (int r = 0; r < 2; ++r)
    for (int b = 0; b < 256; ++b) f.at<float>(r, b) = ((a.at<uint8_t>(r, b / 8) >> (b % 8)) & 1) ? 1.f / 16 : -1.f / 16;
  const float h = RowDistance(a, 0, a, 1);
  CHECK(h == static_cast<float>(DescriptorDistance(a.ptr<uint8_t>(0), a.ptr<uint8_t>(1))));
  CHECK(h == static_cast<float>(HammingBits(a.ptr<uint8_t>(0), a.ptr<uint8_t>(1), 32)));
  CHECK(RowDistance(f, 0, f, 1) == Approx(4.0 * h / 256).epsilon(1e-6));
  // A 9-byte string takes the generic path.
  const cv::Mat b9 = a(cv::Rect(0, 0, 9, 2)).clone();
  CHECK(RowDistance(b9, 0, b9, 1) == static_cast<float>(HammingBits(b9.ptr<uint8_t>(0), b9.ptr<uint8_t>(1), 9)));
  cv::Mat g = (cv::Mat_<float>(2, 2) << 3, 4, 0, 0);
  NormaliseRows(&g);
  CHECK(g.at<float>(0, 0) == Approx(0.6));
  CHECK(g.at<float>(1, 1) == 0);  // a zero row stays zero
}

TEST_CASE("plugin: SIFT gives unit float rows, levels of a 2^(1/3) pyramid and the same bytes twice") {
  ExtractorOptions o;
  o.type = "sift";
  o.sift.n_features = 500;
  auto e = MakeExtractor(o);
  const DescriptorProfile p = e->profile();
  CHECK(p.type == CV_32F);
  CHECK(p.cols == 128);
  CHECK(p.oriented);
  CHECK(p.scale_factor == Approx(std::pow(2.0, 1.0 / 3)));
  REQUIRE_NOTHROW(p.Check());
  const cv::Mat img = Texture(1);
  std::vector<cv::KeyPoint> k1, k2;
  cv::Mat d1, d2;
  e->Extract(img, &k1, &d1);
  e->Extract(img, &k2, &d2);
  REQUIRE(k1.size() > 100);
  CHECK(k1.size() <= 520);  // n_features, plus OpenCV's orientation duplicates
  REQUIRE(d1.rows == static_cast<int>(k1.size()));
  CHECK(d1.type() == CV_32F);
  for (int r = 0; r < d1.rows; ++r) CHECK(cv::norm(d1.row(r)) == Approx(1).epsilon(1e-5));
  for (const cv::KeyPoint& kp : k1) {
    CHECK(kp.octave >= 0);
    CHECK(kp.octave < p.n_levels);
  }
  CHECK(cv::norm(d1, d2, cv::NORM_INF) == 0);
  // Packed octave -> level: octave -1 (upsampled) goes to level 0, octave 2 layer 1 -> 7.
  CHECK(SiftExtractor::Level((1 << 8) | 255, 3, 24) == 0);
  CHECK(SiftExtractor::Level((1 << 8) | 2, 3, 24) == 7);
  CHECK(SiftExtractor::Level((3 << 8) | 9, 3, 24) == 23);
  // A gate override reaches the profile; one above TH_HIGH or the largest distance is an error.
  o.th_low = 0.1;
  CHECK(MakeExtractor(o)->profile().th_low == Approx(0.1f));
  o.th_low = 0.7;
  CHECK_THROWS_AS(MakeExtractor(o), InputError);
  o.th_low = 0, o.th_high = 5;
  CHECK_THROWS_AS(MakeExtractor(o), InputError);
}

TEST_CASE("plugin: SuperPoint score decoding, NMS order and bilinear descriptor sampling") {
  // 65-channel logits over a 16 x 16 image (2 x 2 cells): cell (1, 0) has pixel c = 9 -> (9, 1).
  cv::Mat s = Blob(65, 2, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) BlobAt(s, 64, y, x) = 5;  // dustbin wins everywhere ...
  BlobAt(s, 9, 1, 0) = 20;                                // ... but here
  const cv::Mat scores = DecodeScoreMap(s, 16, 16);
  CHECK(scores.at<float>(9, 1) > 0.99f);
  CHECK(scores.at<float>(0, 0) < 0.01f);
  CHECK_THROWS_AS(DecodeScoreMap(Blob(7, 2, 2), 16, 16), std::invalid_argument);
  // Issue 37: a score map at 2x the expected resolution (65 x 4 x 4 or 1 x 32 x 32 for 16 x 16)
  // placed keypoints at the wrong pixels; refused with the expected shape.
  CHECK_THROWS_WITH(DecodeScoreMap(Blob(65, 4, 4), 16, 16), Catch::Contains("65 x 2 x 2"));
  CHECK_THROWS_WITH(DecodeScoreMap(Blob(1, 32, 32), 16, 16), Catch::Contains("must be 16 x 16"));
  CHECK_NOTHROW(DecodeScoreMap(Blob(1, 16, 16), 16, 16));
  CHECK_NOTHROW(DecodeScoreMap(Blob(65, 2, 2), 12, 12));  // 12 x 12 padded to 16 x 16
  // NMS: (5, 5) 0.9 suppresses (6, 7) 0.8 within radius 2; (10, 10) and (10, 3) tie -> row, then column.
  cv::Mat m(16, 16, CV_32F, cv::Scalar(0));
  m.at<float>(5, 5) = 0.9f, m.at<float>(6, 7) = 0.8f, m.at<float>(10, 10) = 0.5f, m.at<float>(10, 3) = 0.5f;
  m.at<float>(0, 0) = 1.0f;  // in the border
  const auto keys = SelectKeypoints(m, 0.015, 2, 1, 10);
  REQUIRE(keys.size() == 3);
  CHECK(keys[0].pt == cv::Point2f(5, 5));
  CHECK(keys[1].pt == cv::Point2f(3, 10));
  CHECK(keys[2].pt == cv::Point2f(10, 10));
  CHECK(SelectKeypoints(m, 0.015, 2, 1, 2).size() == 2);
  // Descriptors: a 2-channel 2 x 2 map over a 16 x 16 image (cell 8): the cell centres are at
  // pixel 3.5 and 11.5; at u = 7.5 (halfway) the value is the mean of the two columns.
  cv::Mat d = Blob(2, 2, 2);
  BlobAt(d, 0, 0, 0) = 1, BlobAt(d, 0, 0, 1) = 3, BlobAt(d, 1, 0, 0) = -1, BlobAt(d, 1, 0, 1) = -1;
  std::vector<cv::KeyPoint> k = {cv::KeyPoint(7.5f, 3.5f, 1), cv::KeyPoint(0, 0, 1)};
  const cv::Mat raw = SampleDescriptors(d, k, 16, 16, false);
  CHECK(raw.at<float>(0, 0) == Approx(2 / std::sqrt(5.0)));  // (2, -1) normalised
  CHECK(raw.at<float>(1, 0) == Approx(1 / std::sqrt(2.0)));  // clamped to cell (0, 0): (1, -1)
  const int sz[4] = {1, 8, 2, 2};
  cv::Mat d8(4, sz, CV_32F, cv::Scalar(-1));
  BlobAt(d8, 2, 0, 0) = 1, BlobAt(d8, 7, 0, 0) = 1;
  const cv::Mat bits = SampleDescriptors(d8, {cv::KeyPoint(3.5f, 3.5f, 1)}, 16, 16, true);
  REQUIRE(bits.type() == CV_8U);
  CHECK(bits.at<uint8_t>(0, 0) == ((1u << 2) | (1u << 7)));
}

TEST_CASE("plugin: a self-built ONNX SuperPoint finds planted dots and keeps descriptors under a one-cell shift") {
  const std::string model = test::ScratchDir("tiny_onnx") + "/tiny_superpoint.onnx";
  test::TinyModelSpec spec;
  spec.height = 96, spec.width = 128;
  test::WriteTinySuperPoint(model, spec);
  ExtractorOptions o;
  o.type = "onnx";
  o.onnx.model = model;
  auto e = MakeExtractor(o);
  // Dots at 1.0 on a flat 0.2 background, each with two dimmer (0.6) pixels of its own pattern in
  // its cell (a distinct neighbourhood for the descriptor); flat cells stay under the threshold.
  const std::vector<cv::Point> dots = {{21, 18}, {45, 28}, {70, 44}, {93, 61}, {34, 66}, {60, 20}};
  auto draw = [&](int shift) {
    cv::Mat img(spec.height, spec.width, CV_8U, cv::Scalar(51));
    for (size_t i = 0; i < dots.size(); ++i) {
      const cv::Point p = dots[i] + cv::Point(shift, shift);
      img.at<uint8_t>(p) = 255;
      const int cx = p.x / 8 * 8, cy = p.y / 8 * 8;
      img.at<uint8_t>(cy + static_cast<int>(i) % 8, cx + 7 - static_cast<int>(i)) = 153;
      img.at<uint8_t>(cy + 7 - static_cast<int>(i) % 3, cx + static_cast<int>(i)) = 153;
    }
    return img;
  };
  std::vector<cv::KeyPoint> k0, k1;
  cv::Mat d0, d1;
  e->Extract(draw(0), &k0, &d0);
  REQUIRE(k0.size() == dots.size());
  std::vector<cv::Point> found;
  for (const cv::KeyPoint& kp : k0) {
    found.emplace_back(static_cast<int>(kp.pt.x), static_cast<int>(kp.pt.y));
    CHECK(kp.octave == 0);
    CHECK(kp.response > 0.99f);
  }
  for (const cv::Point& p : dots) CHECK(std::find(found.begin(), found.end(), p) != found.end());
  const DescriptorProfile prof = e->profile();
  CHECK(prof.type == CV_32F);
  CHECK(prof.cols == spec.descriptor_dim);
  CHECK(!prof.oriented);
  CHECK(prof.n_levels == 1);
  // One cell (8 px) down and right: the same keypoints moved, the same descriptors, MNN2 pairs
  // every dot with itself.
  e->Extract(draw(8), &k1, &d1);
  REQUIRE(k1.size() == dots.size());
  const auto m = MatchMnn2(d0, d1, Mnn2Options{});
  REQUIRE(m.size() == dots.size());
  for (const DescriptorMatch& x : m) {
    CHECK(k1[size_t(x.j)].pt == k0[size_t(x.i)].pt + cv::Point2f(8, 8));
    CHECK(x.distance < 1e-10);
  }
  // Binary head: the same model with signs packed into D / 8 bytes and Hamming gates.
  o.onnx.binary = true;
  auto eb = MakeExtractor(o);
  std::vector<cv::KeyPoint> kb;
  cv::Mat db;
  eb->Extract(draw(0), &kb, &db);
  CHECK(db.type() == CV_8U);
  CHECK(db.cols == spec.descriptor_dim / 8);
  CHECK(eb->profile().worst == static_cast<float>(spec.descriptor_dim));
}

TEST_CASE("plugin: a missing or broken ONNX model is an error naming the file") {
  ExtractorOptions o;
  o.type = "onnx";
  o.onnx.model = test::ScratchDir("tiny_onnx_bad") + "/missing.onnx";
  try {
    MakeExtractor(o);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("missing.onnx") != std::string::npos);
  }
  o.type = "surf";
  CHECK_THROWS_AS(MakeExtractor(o), InputError);
}

TEST_CASE("descriptor distances: the POPCNT path and the portable one count the same bits as a bit loop", "[features]") {
  uint32_t state = 7;
  std::vector<uint8_t> a(64), b(64);
  for (int trial = 0; trial < 200; ++trial) {
    for (size_t i = 0; i < a.size(); ++i) {
      state = state * 1664525u + 1013904223u;
      a[i] = static_cast<uint8_t>(state >> 24), b[i] = static_cast<uint8_t>(state >> 16);
    }
    for (int n = 1; n <= 64; ++n) {
      int bits = 0;
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < 8; ++k) bits += ((a[i] ^ b[i]) >> k) & 1;
      REQUIRE(HammingBits(a.data(), b.data(), n) == bits);
      REQUIRE(dynref::features::HammingBitsPortableForTest(a.data(), b.data(), n) == bits);
      if (n == 32) REQUIRE(DescriptorDistance(a.data(), b.data()) == bits);
    }
  }
}
