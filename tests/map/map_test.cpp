// Map bookkeeping: observations (RGB-D observations count 2 as in ORB-SLAM2), culling, point
// replacement, covisibility and keyframe removal.
#include <catch2/catch.hpp>

#include "map/map.h"

using namespace dynref;

namespace {
std::unique_ptr<KeyFrame> MakeKf(const Camera& cam, int n, double x) {
  auto kf = std::make_unique<KeyFrame>();
  Frame& f = kf->frame;
  f.depth_m = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(2.0f));
  for (int i = 0; i < n; ++i) f.keys.emplace_back(cv::Point2f(20.f + 10.f * (i % 50), 20.f + 10.f * (i / 50)), 31.f);
  f.descriptors = cv::Mat::zeros(n, 32, CV_8U);
  for (int i = 0; i < n; ++i) f.descriptors.at<uint8_t>(i, 0) = static_cast<uint8_t>(i);
  f.pyramid = ScalePyramid::Make(8, 1.2);
  f.FinishFeatures(cam);
  kf->T_cw.translation() = Eigen::Vector3d(x, 0, 0);
  kf->map_point_ids.assign(n, -1);
  return kf;
}
Camera Cam() {
  Camera c;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  return c;
}
}  // namespace

TEST_CASE("map: observations, erase to bad, replace") {
  const Camera cam = Cam();
  Map map;
  KeyFrame* a = map.AddKeyFrame(MakeKf(cam, 40, 0));
  KeyFrame* b = map.AddKeyFrame(MakeKf(cam, 40, 0.1));
  CHECK(a->id == 0);
  CHECK(b->id == 1);
  MapPoint* p = map.NewMapPoint({0, 0, 2}, a->id, 0);
  map.AddObservation(p->id, a->id, 3);
  map.AddObservation(p->id, b->id, 4);
  CHECK(p->n_obs == 4);  // two RGB-D observations
  CHECK(a->map_point_ids[3] == p->id);
  map.UpdatePointDescriptor(p->id);
  map.UpdatePointNormalAndDepth(p->id);
  CHECK(p->max_distance > p->min_distance);
  MapPoint* q = map.NewMapPoint({0, 0, 2.01}, a->id, 0);
  map.AddObservation(q->id, a->id, 5);
  map.ReplacePoint(q->id, p->id);
  CHECK(q->bad);
  CHECK(q->replaced_by == p->id);
  CHECK(a->map_point_ids[5] == -1);  // p already observed in a
  map.EraseObservation(p->id, b->id);
  CHECK(p->bad);  // 2 counted observations left -> bad (ORB-SLAM2 nObs <= 2)
  CHECK(a->map_point_ids[3] == -1);
}

TEST_CASE("map: covisibility needs 15 shared points, else the best one") {
  const Camera cam = Cam();
  Map map;
  KeyFrame* a = map.AddKeyFrame(MakeKf(cam, 60, 0));
  KeyFrame* b = map.AddKeyFrame(MakeKf(cam, 60, 0.1));
  KeyFrame* c = map.AddKeyFrame(MakeKf(cam, 60, 0.2));
  for (int i = 0; i < 20; ++i) {
    MapPoint* p = map.NewMapPoint({0.01 * i, 0, 2}, a->id, 0);
    map.AddObservation(p->id, a->id, i);
    map.AddObservation(p->id, b->id, i);
    if (i < 5) map.AddObservation(p->id, c->id, i);
  }
  map.UpdateConnections(a->id);
  CHECK(a->connections.at(b->id) == 20);
  CHECK(a->connections.at(c->id) == 5);
  REQUIRE(a->ordered_covisibles.size() == 1);
  CHECK(a->ordered_covisibles[0] == b->id);
  map.UpdateConnections(c->id);
  REQUIRE(c->ordered_covisibles.size() == 1);  // fewer than 15 everywhere: best only
  CHECK(c->ordered_covisibles[0] == a->id);
  b->parent = a->id;
  map.SetBadKeyFrame(b->id);
  CHECK(b->bad);
  CHECK(a->connections.count(b->id) == 0);
  CHECK(map.ResolvedT_cw(b->id).translation().x() == Approx(0.1));
  map.SetBadKeyFrame(a->id);  // keyframe 0 is never removed
  CHECK_FALSE(a->bad);
}
