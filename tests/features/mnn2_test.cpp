// MNN2 matching (seed 004 Sec. 3.2): ratio test, absolute gate and mutual check on hand-made
// float and binary descriptors.
#include <catch2/catch.hpp>

#include "features/mnn2.h"

using namespace dynref::features;

TEST_CASE("mnn2: float descriptors, squared L2 on unit rows, ratio, gate and mutual check") {
  // D0: a = (1,0,0), b = (0,1,0), c = (0.8,0.6,0) (close to a AND fairly close to b).
  // D1: A = (2,0,0) (unit: (1,0,0)), B = (0,0.96,0.28), C = (0,0,1).
  const cv::Mat D0 = (cv::Mat_<float>(3, 3) << 1, 0, 0, 0, 1, 0, 0.8f, 0.6f, 0);
  const cv::Mat D1 = (cv::Mat_<float>(3, 3) << 2, 0, 0, 0, 0.96f, 0.28f, 0, 0, 1);
  Mnn2Options o;  // rho 0.95, tau 1.5625, mutual
  const auto m = MatchMnn2(D0, D1, o);
  // a -> A: d = 0, second 2 -> accepted, and A's nearest in D0 is a (0 < |c - A|^2 = 0.4).
  // b -> B: d = 0.0784 + 0.0784 = 0.0016 + 0.0784? |(0,1,0)-(0,0.96,0.28)|^2 = 0.0016 + 0.0784 = 0.08;
  //         second |b - A|^2 = 2 -> accepted; B's nearest in D0: b (0.08) vs c (0.64 + 0.1296 + 0.0784 = 0.848).
  // c -> A: d = 0.04 + 0.36 = 0.4; second c -> B = 0.848: 0.4 < 0.95 * 0.848 passes, but A's nearest is a: not mutual.
  REQUIRE(m.size() == 2);
  CHECK(m[0].i == 0);
  CHECK(m[0].j == 0);
  CHECK(m[0].distance == Approx(0).margin(1e-12));
  CHECK(m[1].i == 1);
  CHECK(m[1].j == 1);
  CHECK(m[1].distance == Approx(0.08).margin(1e-6));
  CHECK(m[1].second == Approx(2.0).margin(1e-6));
  o.mutual = false;
  const auto n = MatchMnn2(D0, D1, o);
  REQUIRE(n.size() == 3);
  CHECK(n[2].i == 2);
  CHECK(n[2].j == 0);
  CHECK(n[2].distance == Approx(0.4).margin(1e-6));
  // A tight ratio drops c -> A (0.4 / 0.848 = 0.47); a tight gate drops b -> B (0.08).
  o.ratio = 0.4;
  CHECK(MatchMnn2(D0, D1, o).size() == 2);
  o.ratio = 0.95, o.tau_float = 0.05;
  CHECK(MatchMnn2(D0, D1, o).size() == 1);
  // Plain nearest neighbour ("BF"): every row matched.
  CHECK(MatchNearest(D0, D1).size() == 3);
}

TEST_CASE("mnn2: binary descriptors by Hamming bits, ambiguous ties rejected") {
  cv::Mat D0 = cv::Mat::zeros(2, 32, CV_8U), D1 = cv::Mat::zeros(3, 32, CV_8U);
  D0.at<uint8_t>(1, 0) = 0xFF;                       // row 1: 8 bits set
  D1.at<uint8_t>(0, 1) = 0x01;                       // 1 bit from D0 row 0
  D1.at<uint8_t>(1, 0) = 0xFF, D1.at<uint8_t>(1, 5) = 0x03;  // 2 bits from D0 row 1
  D1.at<uint8_t>(2, 9) = 0x01;                       // also 1 bit from D0 row 0: a tie
  Mnn2Options o;
  // Row 0: nearest 1 bit (D1 row 0), second 1 bit (row 2): 1 < 0.95 * 1 fails -> rejected.
  // Row 1: D1 row 1 at 2 bits, second 9 bits -> accepted, mutual.
  const auto m = MatchMnn2(D0, D1, o);
  REQUIRE(m.size() == 1);
  CHECK(m[0].i == 1);
  CHECK(m[0].j == 1);
  CHECK(m[0].distance == 2);
  CHECK(m[0].second == 9);
  o.tau_bits = 2;  // gate is strict: 2 bits no longer pass
  CHECK(MatchMnn2(D0, D1, o).empty());
  CHECK_THROWS(MatchMnn2(D0, cv::Mat::zeros(2, 16, CV_8U), o));
}
