// Frame: depth lookup, virtual right coordinate, grid search, exclusion and weights.
#include <catch2/catch.hpp>

#include "map/frame.h"

using dynref::Camera;
using dynref::Frame;

namespace {
Frame MakeFrame(const Camera& cam) {
  Frame f;
  f.index = 7;
  f.depth_m = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(2.0f));
  f.depth_m.at<float>(100, 50) = 0.0f;  // hole under the second key
  for (int i = 0; i < 20; ++i) {
    cv::KeyPoint kp(cv::Point2f(10.f + 30.f * i, 100.f), 31.f, 0.f, 1.f, i % 3);
    f.keys.push_back(kp);
  }
  f.keys[1].pt = {50.f, 100.f};
  f.descriptors = cv::Mat::zeros(20, 32, CV_8U);
  f.pyramid = dynref::ScalePyramid::Make(8, 1.2);
  f.FinishFeatures(cam);
  return f;
}
Camera FrameCam() {
  Camera c;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  c.bf = 40;
  return c;
}
}  // namespace

TEST_CASE("frame: depth per key and virtual right u = u - bf / z") {
  const Camera cam = FrameCam();
  const Frame f = MakeFrame(cam);
  REQUIRE(f.N() == 20);
  CHECK(f.depth[0] == Approx(2.0));
  CHECK(f.u_right[0] == Approx(10.0 - 40.0 / 2.0));
  CHECK(f.depth[1] < 0);
  CHECK(f.u_right[1] < 0);
  CHECK(f.IsClose(0));  // 2 m < 40 * 0.08 m
  const Eigen::Vector3d X = f.UnprojectWorld(0);
  CHECK(X.z() == Approx(2.0));
  CHECK(X.x() == Approx((10.0 - 320.0) * 2.0 / 500.0));
}

TEST_CASE("frame: area search honours radius, levels and exclusion") {
  const Camera cam = FrameCam();
  Frame f = MakeFrame(cam);
  auto in = f.FeaturesInArea(100.f, 100.f, 16.f);
  REQUIRE(in.size() == 1);
  CHECK(in[0] == 3);  // x = 100
  in = f.FeaturesInArea(100.f, 100.f, 40.f);
  CHECK(in.size() == 3);
  in = f.FeaturesInArea(100.f, 100.f, 40.f, 1, 1);  // octave of key 2,3,4 = 2,0,1
  REQUIRE(in.size() == 1);
  CHECK(in[0] == 4);
  f.map_point_ids[3] = 42;
  f.Exclude(3, "test.stage", "because");
  CHECK(f.IsExcluded(3));
  CHECK(f.map_point_ids[3] == -1);
  CHECK(f.ExcludedCount() == 1);
  in = f.FeaturesInArea(100.f, 100.f, 16.f);
  CHECK(in.empty());
}

TEST_CASE("frame: weights default to 1 and are per feature") {
  const Camera cam = FrameCam();
  Frame f = MakeFrame(cam);
  CHECK(f.Weight(5) == 1.0);
  f.SetWeight(5, 0.25);
  CHECK(f.Weight(5) == 0.25);
  CHECK(f.Weight(6) == 1.0);
  CHECK(f.FeatureId(5) == "f7.5");
}

TEST_CASE("frame: depth_edge_rel drops the depth of keypoints on depth discontinuities only") {
  const Camera cam = FrameCam();
  Frame f;
  f.depth_m = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(2.0f));
  f.depth_m(cv::Rect(300, 0, 340, cam.height)).setTo(3.0f);  // a 1 m step at column 300
  f.depth_m.at<float>(200, 101) = 0.0f;                       // a hole next to key 2
  f.depth_m.at<float>(50, 52) = 2.08f;                        // 4 % away from key 3's 2 m
  for (const cv::Point2f p : {cv::Point2f(100.f, 100.f), cv::Point2f(299.f, 100.f), cv::Point2f(100.f, 200.f),
                              cv::Point2f(50.f, 50.f), cv::Point2f(301.f, 100.f)})
    f.keys.emplace_back(p, 31.f, 0.f, 1.f, 0);
  f.descriptors = cv::Mat::zeros(5, 32, CV_8U);
  f.pyramid = dynref::ScalePyramid::Make(8, 1.2);
  f.FinishFeatures(cam);  // ORB-SLAM2: every key with depth at its pixel
  CHECK(f.depth[0] == 2.0f);
  CHECK(f.depth[1] == 2.0f);
  CHECK(f.depth[2] == 2.0f);
  CHECK(f.depth[4] == 3.0f);
  f.FinishFeatures(cam, 0.05);
  CHECK(f.depth[0] == 2.0f);  // flat
  CHECK(f.depth[1] < 0);      // column 301 (in its 5x5 window) is 1 m deeper
  CHECK(f.u_right[1] < 0);
  CHECK(f.depth[2] < 0);      // a pixel without depth in the window
  CHECK(f.depth[3] == 2.0f);  // 4 % < 5 %
  CHECK(f.depth[4] < 0);      // the far side of the same step
  f.FinishFeatures(cam, 0.03);
  CHECK(f.depth[3] < 0);  // 4 % > 3 %
}

TEST_CASE("frame: the association an exclusion or DropAssociation removes is remembered (trace OBS)") {
  const Camera cam = FrameCam();
  Frame f = MakeFrame(cam);
  for (int i = 0; i < 20; ++i) CHECK(f.AssociatedMapPoint(i) == -1);  // never associated
  f.map_point_ids[2] = 40;
  f.map_point_ids[3] = 41;
  f.map_point_ids[4] = 42;
  f.Exclude(2, "test.stage", "dynamic");
  CHECK(f.map_point_ids[2] == -1);       // Exclude still removes the association (issue 5 contract)
  CHECK(f.AssociatedMapPoint(2) == 40);  // ... but the trace can name the point the stage saw
  f.DropAssociation(3);                  // e.g. a final-optimisation outlier
  CHECK(f.map_point_ids[3] == -1);
  CHECK(f.AssociatedMapPoint(3) == 41);
  f.outlier[4] = 1;                      // flagged, still associated
  CHECK(f.AssociatedMapPoint(4) == 42);
  f.DropAssociation(5);                  // nothing to drop
  CHECK(f.AssociatedMapPoint(5) == -1);
  f.Exclude(6, "test.stage", "before tracking");  // excluded before any association
  CHECK(f.AssociatedMapPoint(6) == -1);
  f.map_point_ids[3] = 77;               // re-associated: the current one wins
  CHECK(f.AssociatedMapPoint(3) == 77);
  f.FinishFeatures(cam);                 // a new frame forgets everything
  CHECK(f.AssociatedMapPoint(2) == -1);
}
