#include <catch2/catch.hpp>

#include "dense/dense_map.h"

using namespace dynref;
using namespace dynref::dense;

namespace {
Camera SmallCamera() {
  Camera c;
  c.width = 64, c.height = 48;
  c.fx = c.fy = 50, c.cx = 32, c.cy = 24;
  return c;
}
}  // namespace

TEST_CASE("dense map: back-projection skips masked pixels and bad depth, colours by class") {
  const Camera cam = SmallCamera();
  cv::Mat bgr(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  cv::Mat depth(48, 64, CV_32F, cv::Scalar(2.0f));
  depth.at<float>(0, 0) = 0;       // invalid
  depth.at<float>(0, 1) = 7.0f;    // beyond max_depth_m
  cv::Mat exclude = cv::Mat::zeros(48, 64, CV_8U);
  exclude(cv::Rect(0, 10, 64, 10)).setTo(255);
  cv::Mat labels(48, 64, CV_16S, cv::Scalar(-1));
  labels(cv::Rect(0, 40, 64, 8)).setTo(62);
  DenseMapOptions o;
  const PointCloud c = BackProjectKeyframe(bgr, depth, exclude, labels, cam, o);
  CHECK(c.size() == 64 * 48 - 2 - 640);
  const ColoredPoint& centre = c[(24 - 10) * 64 + 32 - 2];  // rows 0..9 kept, (0,0),(0,1) dropped
  CHECK(centre.x == Approx(0).margin(1e-6));
  CHECK(centre.z == 2.0f);
  CHECK(centre.r == 30);
  CHECK(centre.b == 10);
  CHECK(c.back().g == 255);  // class 62 (tv/monitor) coloured green
  CHECK(c.back().r == 0);
  CHECK(c.back().class_id == 62);
}

TEST_CASE("dense map: keyframes accumulate, global filter every N keyframes, deterministic") {
  const Camera cam = SmallCamera();
  cv::Mat bgr(48, 64, CV_8UC3, cv::Scalar(50, 60, 70));
  cv::Mat depth(48, 64, CV_32F, cv::Scalar(1.0f));
  DenseMapOptions o;
  o.filter_every_keyframes = 2;
  o.keyframe_leaf_m = 0.05;  // pixel footprint at 1 m is 2 cm: 2-3 pixels per voxel side
  o.sor.k = 8;
  DenseMap map(o);
  SE3 T_wc = SE3::Identity();
  const KeyframeInsertStats s1 = map.AddKeyframe(bgr, depth, {}, {}, cam, T_wc);
  CHECK(!s1.global_filter_ran);
  CHECK(s1.back_projected == 64 * 48);
  CHECK(s1.after_voxel < s1.back_projected / 4);
  T_wc.translation() = Eigen::Vector3d(0.005, 0, 0);
  const KeyframeInsertStats s2 = map.AddKeyframe(bgr, depth, {}, {}, cam, T_wc);
  CHECK(s2.global_filter_ran);
  CHECK(map.keyframes() == 2);
  CHECK(map.Finish() == 0);  // nothing added since the last filter
  DenseMap again(o);
  again.AddKeyframe(bgr, depth, {}, {}, cam, SE3::Identity());
  again.AddKeyframe(bgr, depth, {}, {}, cam, T_wc);
  CHECK(!map.cloud().empty());
  REQUIRE(again.cloud().size() == map.cloud().size());
  for (size_t i = 0; i < map.cloud().size(); ++i) CHECK(again.cloud()[i].x == map.cloud()[i].x);
  o.pixel_stride = 0;
  CHECK_THROWS_WITH(o.Check(), Catch::Contains("pixel_stride"));
}

TEST_CASE("dense map: a distorted camera back-projects each raw pixel along its undistorted ray (issue 21 defect 4)") {
  const Camera cam = CameraPreset("tum_fr1");
  const cv::Mat rays = UndistortedRays(cam);
  REQUIRE(!rays.empty());
  CHECK(UndistortedRays(CameraPreset("tum_fr3")).empty());  // no distortion: pinhole as before
  const cv::Mat bgr(cam.height, cam.width, CV_8UC3, cv::Scalar(10, 20, 30));
  const cv::Mat depth(cam.height, cam.width, CV_32F, cv::Scalar(2.0f));
  DenseMapOptions o;
  o.pixel_stride = 40;
  const PointCloud c = BackProjectKeyframe(bgr, depth, cv::Mat(), cv::Mat(), cam, o, rays);
  REQUIRE(!c.empty());
  // Point 0 is raw pixel (0, 0): projected (pinhole) and distorted it lands back on (0, 0).
  const cv::Point2d px = cam.Distort(cam.fx * c[0].x / c[0].z + cam.cx, cam.fy * c[0].y / c[0].z + cam.cy);
  CHECK(px.x == Approx(0).margin(0.02));
  CHECK(px.y == Approx(0).margin(0.02));
  // The pinhole reading (no rays) puts the corner pixel elsewhere by several pixels.
  const PointCloud p = BackProjectKeyframe(bgr, depth, cv::Mat(), cv::Mat(), cam, o);
  const cv::Point2d q = cam.Distort(cam.fx * p[0].x / p[0].z + cam.cx, cam.fy * p[0].y / p[0].z + cam.cy);
  CHECK(std::hypot(q.x, q.y) > 2.0);
}
