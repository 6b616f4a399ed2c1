#include <catch2/catch.hpp>

#include <opencv2/calib3d.hpp>

#include "dynamic/sgdo/depth_consistency.h"

using namespace dynref::sgdo;

namespace {
const dynref::Intrinsics kK{535.4, 539.2, 320.1, 247.6};

// Keyframe looking at a fronto-parallel wall at `z` m.
cv::Mat Wall(float z) { return cv::Mat(480, 640, CV_32F, cv::Scalar(z)); }
}  // namespace

TEST_CASE("sgdo depth: static point on a wall is consistent after camera motion") {
  // Current camera 0.2 m closer to the wall than the keyframe: T_kc translates by -0.2 in z.
  Eigen::Isometry3d T_kc = Eigen::Isometry3d::Identity();
  T_kc.translation() = Eigen::Vector3d(0.05, 0, 0.2);
  const DepthCheck c = CheckDepthConsistency(300, 200, 1.8, kK, T_kc, Wall(2.0f));
  REQUIRE(c.tested);
  CHECK(c.z_k == Approx(2.0));
  CHECK(c.eps == Approx(0.0).margin(1e-6));
  CHECK(c.u_k == Approx(320.1 + 535.4 * ((300 - 320.1) / 535.4 * 1.8 + 0.05) / 2.0));
  CHECK(StaticWeight(c.eps, 100) == Approx(1.0));
}

TEST_CASE("sgdo depth: a person in front of the wall gives a large residual") {
  // Point at 1.5 m now; in the keyframe the pixel saw the wall at 2.0 m.
  const DepthCheck c =
      CheckDepthConsistency(320, 240, 1.5, kK, Eigen::Isometry3d::Identity(), Wall(2.0f));
  REQUIRE(c.tested);
  CHECK(c.eps == Approx(-0.25));
  DepthConsistencyOptions o;
  CHECK(std::abs(c.eps) > o.eta);
  CHECK(StaticWeight(c.eps, o.lambda) == Approx(std::exp(-6.25)));
  CHECK(StaticWeight(o.eta, o.lambda) == Approx(std::exp(-1.0)));  // lambda = 1/eta^2
}

TEST_CASE("sgdo depth: skipped tests keep the point (spec 001 step 5)") {
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  CHECK(CheckDepthConsistency(320, 240, 0.0, kK, I, Wall(2.0f)).skip_reason == "no-depth");
  Eigen::Isometry3d behind = I;
  behind.translation() = Eigen::Vector3d(0, 0, -3);
  CHECK(CheckDepthConsistency(320, 240, 2.0, kK, behind, Wall(2.0f)).skip_reason == "behind-kf");
  Eigen::Isometry3d side = I;
  side.translation() = Eigen::Vector3d(5, 0, 0);
  CHECK(CheckDepthConsistency(320, 240, 2.0, kK, side, Wall(2.0f)).skip_reason == "outside-kf");
  cv::Mat holes = Wall(2.0f);
  holes.at<float>(240, 320) = 0;
  const DepthCheck h = CheckDepthConsistency(320, 240, 2.0, kK, I, holes);
  CHECK(h.skip_reason == "kf-no-depth");
  CHECK(!h.tested);
  CHECK(h.eps == 0);
  DepthConsistencyOptions bad;
  bad.eta = 0;
  CHECK_THROWS_WITH(bad.Check(), Catch::Contains("eta"));
}

TEST_CASE("sgdo depth: a distorted keyframe depth image is read at the distorted pixel (issue 21 defect 4)") {
  // TUM fr1 distortion. The keyframe sees a slanted wall z(y_n) = 3 + 5 y_n (y_n = normalised
  // undistorted image y); its RAW depth image holds at raw pixel (u, v) the depth of the ray
  // through the undistorted position of (u, v).
  dynref::Camera cam = dynref::CameraPreset("tum_fr1");
  cv::Mat depth(cam.height, cam.width, CV_32F);
  std::vector<cv::Point2d> raw, und;
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) raw.emplace_back(u, v);
  cv::undistortPoints(raw, und, cv::Mat(cam.K()), cam.DistCoeffs());
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) depth.at<float>(v, u) = float(3.0 + 5.0 * und[size_t(v) * cam.width + u].y);
  const dynref::Intrinsics K = cam.Pinhole();
  // A static point near the image corner (undistorted pixel), current frame = keyframe.
  const double u = 60, v = 40, y_n = (v - K.cy) / K.fy, z = 3.0 + 5.0 * y_n;
  const DepthCheck with = CheckDepthConsistency(u, v, z, K, Eigen::Isometry3d::Identity(), depth, &cam);
  REQUIRE(with.tested);
  CHECK(std::abs(with.eps) < 0.01);  // consistent: read at the distorted pixel
  const DepthCheck without = CheckDepthConsistency(u, v, z, K, Eigen::Isometry3d::Identity(), depth);
  REQUIRE(without.tested);
  CHECK(std::abs(without.eps) > 0.03);  // the old reading: another part of the wall
  // Camera::Distort inverts undistortPoints.
  const cv::Point2d back = cam.Distort(K.fx * und[50 * cam.width + 70].x + K.cx, K.fy * und[50 * cam.width + 70].y + K.cy);
  CHECK(back.x == Approx(70).margin(0.01));
  CHECK(back.y == Approx(50).margin(0.01));
}
