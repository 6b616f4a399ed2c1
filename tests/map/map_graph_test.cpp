// The keyframe graphs of the map (ORB-SLAM2 semantics): covisibility weights and their order,
// keyframe culling, and the spanning tree a culled keyframe's children and pose are re-linked
// through.
#include <catch2/catch.hpp>

#include "map/map.h"

using namespace dynref;

namespace {

Camera GraphCam() {
  Camera c;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  return c;
}

// A keyframe with n keypoints on a grid, all at 2 m depth (RGB-D: every observation counts 2).
std::unique_ptr<KeyFrame> GraphKf(int n, double x) {
  const Camera cam = GraphCam();
  auto kf = std::make_unique<KeyFrame>();
  Frame& f = kf->frame;
  f.depth_m = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(2.0f));
  for (int i = 0; i < n; ++i) f.keys.emplace_back(cv::Point2f(20.f + 10.f * (i % 50), 20.f + 10.f * (i / 50)), 31.f);
  f.descriptors = cv::Mat::zeros(n, 32, CV_8U);
  f.pyramid = ScalePyramid::Make(8, 1.2);
  f.FinishFeatures(cam);
  kf->T_cw.translation() = Eigen::Vector3d(x, 0.05 * x, 0);
  kf->map_point_ids.assign(static_cast<size_t>(n), -1);
  return kf;
}

// `count` new points seen by every keyframe of `kfs` at keypoints first, first + 1, ...
void Share(Map& map, const std::vector<KeyFrame*>& kfs, int first, int count) {
  for (int i = first; i < first + count; ++i) {
    MapPoint* p = map.NewMapPoint({0.01 * i, 0, 2}, kfs.front()->id, 0);
    for (KeyFrame* k : kfs) map.AddObservation(p->id, k->id, i);
  }
}

}  // namespace

TEST_CASE("map covisibility: weights are symmetric, ordered by weight then id, filtered by count and weight") {
  Map map;
  KeyFrame* a = map.AddKeyFrame(GraphKf(100, 0));
  KeyFrame* b = map.AddKeyFrame(GraphKf(100, 0.1));
  KeyFrame* c = map.AddKeyFrame(GraphKf(100, 0.2));
  KeyFrame* d = map.AddKeyFrame(GraphKf(100, 0.3));
  Share(map, {a, b}, 0, 30);
  Share(map, {a, d}, 30, 20);
  Share(map, {a, c}, 50, 20);  // the same weight as d: the lower id (c) comes first
  map.UpdateConnections(a->id);
  CHECK(a->connections == std::map<int64_t, int>{{b->id, 30}, {c->id, 20}, {d->id, 20}});
  CHECK(a->ordered_covisibles == std::vector<int64_t>{b->id, c->id, d->id});
  // The other side learns the edge too (ORB-SLAM2 AddConnection).
  CHECK(b->connections.at(a->id) == 30);
  CHECK(c->ordered_covisibles == std::vector<int64_t>{a->id});
  CHECK(a->BestCovisibles(2) == std::vector<int64_t>{b->id, c->id});
  CHECK(a->BestCovisibles(10).size() == 3);
  CHECK(a->CovisiblesWithWeight(25) == std::vector<int64_t>{b->id});
  CHECK(a->CovisiblesWithWeight(20).size() == 3);
  // A culled neighbour leaves the graph of its covisibles.
  map.SetBadKeyFrame(c->id);
  CHECK(a->connections.count(c->id) == 0);
  CHECK(a->ordered_covisibles == std::vector<int64_t>{b->id, d->id});
  map.UpdateConnections(a->id);  // bad keyframes are not counted again
  CHECK(a->connections.count(c->id) == 0);
}

TEST_CASE("map culling: the culled keyframe's observations go, its points survive with enough others") {
  Map map;
  KeyFrame* k0 = map.AddKeyFrame(GraphKf(40, 0));
  KeyFrame* k1 = map.AddKeyFrame(GraphKf(40, 0.1));
  KeyFrame* k2 = map.AddKeyFrame(GraphKf(40, 0.2));
  k1->parent = k0->id;
  k2->parent = k1->id;
  Share(map, {k0, k1, k2}, 0, 5);  // 3 RGB-D observations: 6 counted
  Share(map, {k1, k2}, 5, 5);      // 2 RGB-D observations: 4 counted
  map.SetBadKeyFrame(k1->id);
  REQUIRE(k1->bad);
  CHECK(k1->frame.depth_m.empty());  // images released
  for (int64_t id = 0; id < 5; ++id) {
    const MapPoint* p = map.mp(id);
    CHECK_FALSE(p->bad);
    CHECK(p->observations.count(k1->id) == 0);
    CHECK(p->n_obs == 4);
  }
  for (int64_t id = 5; id < 10; ++id) CHECK(map.mp(id)->bad);  // one keyframe left: ORB-SLAM2 nObs <= 2
  CHECK(map.GoodPointCount() == 5);
  // Keyframe 0 and a keyframe marked not_erase are never culled.
  map.SetBadKeyFrame(k0->id);
  CHECK_FALSE(k0->bad);
  k2->not_erase = true;
  map.SetBadKeyFrame(k2->id);
  CHECK_FALSE(k2->bad);
}

TEST_CASE("map spanning tree: children move to the culled keyframe's parent, its pose follows the chain") {
  Map map;
  KeyFrame* k0 = map.AddKeyFrame(GraphKf(20, 0));
  KeyFrame* k1 = map.AddKeyFrame(GraphKf(20, 0.1));
  KeyFrame* k2 = map.AddKeyFrame(GraphKf(20, 0.2));
  KeyFrame* k3 = map.AddKeyFrame(GraphKf(20, 0.3));
  KeyFrame* k4 = map.AddKeyFrame(GraphKf(20, 0.4));
  k1->parent = k0->id;
  k2->parent = k1->id;
  k3->parent = k2->id;
  k4->parent = k2->id;
  k1->T_cw.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const SE3 T1 = k1->T_cw, T2 = k2->T_cw;
  map.SetBadKeyFrame(k2->id);
  CHECK(k3->parent == k1->id);
  CHECK(k4->parent == k1->id);
  CHECK(k2->parent == k1->id);  // a culled keyframe keeps its own parent (its T_cp is relative to it)
  map.SetBadKeyFrame(k1->id);
  CHECK(k3->parent == k0->id);
  CHECK(k4->parent == k0->id);
  CHECK(k2->parent == k1->id);  // culled children are not re-linked
  // A culled keyframe's pose is its T_cp chain up to the first live ancestor.
  CHECK((map.ResolvedT_cw(k2->id).matrix() - T2.matrix()).norm() < 1e-12);
  CHECK((map.ResolvedT_cw(k1->id).matrix() - T1.matrix()).norm() < 1e-12);
  // Moving the live root moves every culled descendant with it.
  k0->T_cw.translation() += Eigen::Vector3d(1, 0, 0);
  const SE3 moved = k2->T_cp * k1->T_cp * k0->T_cw;
  CHECK((map.ResolvedT_cw(k2->id).matrix() - moved.matrix()).norm() < 1e-12);
  CHECK(map.ResolvedT_cw(k3->id).translation().x() == Approx(0.3));  // live: its own pose
}
