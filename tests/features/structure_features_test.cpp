// Lines (FLD + LBD, parallel groups) and AHC planes on planted images (issue 13).
#include <catch2/catch.hpp>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "features/lines.h"
#include "features/planes.h"

using namespace dynref;
using namespace dynref::features;

namespace {

Intrinsics Kinect() {
  Intrinsics K;
  K.fx = 525, K.fy = 525, K.cx = 319.5, K.cy = 239.5, K.width = 640, K.height = 480;
  return K;
}

// Depth of the plane n^T X + d = 0 along the ray of pixel (u, v); 0 when behind or parallel.
float RayDepth(const Intrinsics& K, const Eigen::Vector3d& n, double d, int u, int v) {
  const Eigen::Vector3d ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
  const double den = n.dot(ray);
  if (std::fabs(den) < 1e-9) return 0.f;
  const double z = -d / den;
  return z > 0 ? static_cast<float>(z) : 0.f;
}

}  // namespace

TEST_CASE("lines: a drawn rectangle gives two parallel groups with companions and LBD rows") {
  cv::Mat img(480, 640, CV_8U, cv::Scalar(40));
  cv::rectangle(img, cv::Rect(150, 120, 300, 200), cv::Scalar(220), cv::FILLED);
  const SegmentSet set = DetectSegments(img, LineOptions{});
  REQUIRE(set.segments.size() >= 4);
  REQUIRE(set.descriptors.rows == static_cast<int>(set.segments.size()));
  REQUIRE(set.descriptors.cols == 32);
  int horizontal = 0, vertical = 0;
  for (const Segment& s : set.segments) {
    const bool h = LineAngleDiff(s.angle, 0) < 0.02, v = LineAngleDiff(s.angle, M_PI / 2) < 0.02;
    CHECK((h || v));
    horizontal += h, vertical += v;
    REQUIRE(s.companion >= 0);  // every side has a parallel partner
    CHECK(set.segments[static_cast<size_t>(s.companion)].group == s.group);
    CHECK(LineAngleDiff(set.segments[static_cast<size_t>(s.companion)].angle, s.angle) < 3 * M_PI / 180);
  }
  CHECK(horizontal >= 2);
  CHECK(vertical >= 2);
  // Two groups only: horizontal ones and vertical ones.
  for (const Segment& a : set.segments)
    for (const Segment& b : set.segments)
      CHECK((a.group == b.group) == (LineAngleDiff(a.angle, b.angle) < 3 * M_PI / 180));
  // Deterministic.
  const SegmentSet again = DetectSegments(img, LineOptions{});
  REQUIRE(again.segments.size() == set.segments.size());
  CHECK(cv::norm(again.descriptors, set.descriptors, cv::NORM_HAMMING) == 0);
}

TEST_CASE("lines: grouping is by orientation mod 180 with the 3 degree gate, companion ties go to the longer") {
  std::vector<Segment> s(4);
  // Angles in exact binary fractions so that equal differences are equal doubles.
  s[0].angle = 0.03125, s[0].length = 50;
  s[1].angle = 0.0, s[1].length = 30;     // 0.03125 rad (1.8 deg) from s[0]
  s[2].angle = 0.0625, s[2].length = 60;  // 0.03125 rad from s[0], 0.0625 (3.6 deg) from s[1]
  s[3].angle = 0.5, s[3].length = 100;    // alone
  GroupParallel(&s, 3.0);
  CHECK(s[0].group == s[1].group);
  CHECK(s[0].group == s[2].group);
  CHECK(s[3].group != s[0].group);
  CHECK(s[3].companion == -1);
  CHECK(s[0].companion == 2);  // equally close to s[1] and s[2]: the longer one
  CHECK(s[1].companion == 0);  // closer to s[0] than to s[2]
  // Across the 180 deg wrap: pi - 0.01 is 0.01 rad from 0.
  std::vector<Segment> w(2);
  w[0].angle = 0.0, w[1].angle = M_PI - 0.01;
  GroupParallel(&w, 3.0);
  CHECK(w[0].group == w[1].group);
}

TEST_CASE("lines: LineThrough gives signed pixel distances") {
  const Eigen::Vector3d l = LineThrough({0, 0}, {10, 0});
  CHECK(std::fabs(l.dot(Eigen::Vector3d(5, 3, 1))) == Approx(3.0));
  CHECK(l.dot(Eigen::Vector3d(5, 0, 1)) == Approx(0.0).margin(1e-12));
}

TEST_CASE("planes: FitPlane recovers a planted plane, normal towards the camera") {
  PlaneFitSums f;
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.3, -1).normalized();
  const double d = 2.0;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      const double x = 0.1 * i - 0.5, y = 0.1 * j - 0.5;
      const double z = -(d + n.x() * x + n.y() * y) / n.z();
      f.Add({x, y, z});
    }
  Eigen::Vector3d nn;
  double dd, mse;
  REQUIRE(FitPlane(f, &nn, &dd, &mse));
  CHECK((nn - n).norm() < 1e-9);
  CHECK(dd == Approx(d));
  CHECK(mse < 1e-18);
}

TEST_CASE("planes: AHC finds a floor, a wall and a box face in a planted depth image and labels them") {
  const Intrinsics K = Kinect();
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(0));
  const Eigen::Vector3d wall(0, 0, -1), floor(0, -1, 0), side = Eigen::Vector3d(1, 0, -1).normalized();
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      float z = RayDepth(K, wall, 3.0, u, v);  // wall at z = 3
      const float zf = RayDepth(K, floor, 1.0, u, v);  // floor 1 m below the camera (y down)
      if (zf > 0 && zf < z) z = zf;
      if (u < 200) {  // a slanted face in front on the left
        const float zs = RayDepth(K, side, 1.2, u, v);
        if (zs > 0 && zs < z) z = zs;
      }
      depth.at<float>(v, u) = z;
    }
  const PlaneSegmentation seg = SegmentPlanes(depth, K, PlaneOptions{});
  REQUIRE(seg.planes.size() >= 3);
  int found = 0;
  for (const Eigen::Vector3d& n : {wall, floor, side}) {
    for (const PlaneObservation& p : seg.planes)
      if (p.n.dot(n) > std::cos(2 * M_PI / 180)) {
        ++found;
        const double expected_d = n == wall ? 3.0 : n == floor ? 1.0 : 1.2;
        CHECK(p.d == Approx(expected_d).epsilon(0.01));
        CHECK(p.area_m2 >= 0.05);
        break;
      }
  }
  CHECK(found == 3);
  // Labels index the planes and cover most of the wall's pixels near the top centre.
  const int l = seg.labels.at<int16_t>(100, 500);
  REQUIRE(l >= 0);
  CHECK(seg.planes[static_cast<size_t>(l)].n.dot(wall) > 0.999);
  // Deterministic.
  const PlaneSegmentation again = SegmentPlanes(depth, K, PlaneOptions{});
  REQUIRE(again.planes.size() == seg.planes.size());
  CHECK(cv::norm(again.labels, seg.labels, cv::NORM_INF) == 0);
}

TEST_CASE("planes: a plane smaller than T_plane is dropped, bad options are refused") {
  const Intrinsics K = Kinect();
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(0));
  depth(cv::Rect(300, 220, 60, 60)).setTo(2.0);  // 60 x 60 px at 2 m: 0.052 m^2 ... at stride 2
  PlaneOptions o;
  o.min_support = 100;
  o.min_area_m2 = 0.5;
  CHECK(SegmentPlanes(depth, K, o).planes.empty());
  o.min_area_m2 = 0.01;
  CHECK(SegmentPlanes(depth, K, o).planes.size() == 1);
  o.block = 1;
  CHECK_THROWS_AS(SegmentPlanes(depth, K, o), std::invalid_argument);
}
