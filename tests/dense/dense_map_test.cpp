#include <catch2/catch.hpp>

#include "dense/dense_map.h"

using namespace dynref;
using namespace dynref::dense;

namespace {
// A fronto-parallel wall 2 m in front of the synthetic camera, one colour.
struct Wall {
  dynref::Camera cam = dynref::CameraPreset("synthetic");
  cv::Mat bgr = cv::Mat(cam.height, cam.width, CV_8UC3, cv::Scalar(40, 80, 120));
  cv::Mat depth = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(2.0f));
};

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
  // --threads (issue 18): bands of rows side by side, concatenated in row order.
  for (int threads : {2, 3, 4}) {
    const PointCloud t = BackProjectKeyframe(bgr, depth, exclude, labels, cam, o, cv::Mat(), threads);
    REQUIRE(t.size() == c.size());
    bool same = true;
    for (size_t i = 0; i < c.size(); ++i)
      same = same && t[i].x == c[i].x && t[i].y == c[i].y && t[i].z == c[i].z && t[i].r == c[i].r &&
             t[i].g == c[i].g && t[i].b == c[i].b && t[i].class_id == c[i].class_id;
    CHECK(same);
  }
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

TEST_CASE("dense map: incremental filtering = SOR of new points against the map around them, voxel grid never re-voxelised") {
  using namespace dynref;
  using namespace dynref::dense;
  // VoxelGrid in two batches equals VoxelDownsample of the union.
  PointCloud a, b;
  for (int i = 0; i < 200; ++i) {
    ColoredPoint p;
    p.x = 0.013f * float(i % 20), p.y = 0.017f * float(i / 20), p.z = 1.0f;
    p.r = uint8_t(i), p.class_id = int16_t(i % 3);
    (i < 120 ? a : b).push_back(p);
  }
  VoxelGrid g(0.05);
  g.Add(a);
  g.Add(b);
  PointCloud all = a;
  all.insert(all.end(), b.begin(), b.end());
  const PointCloud ref = VoxelDownsample(all, 0.05);
  const PointCloud inc = g.Cloud();
  REQUIRE(inc.size() == ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    CHECK(inc[i].x == ref[i].x);
    CHECK(inc[i].r == ref[i].r);
    CHECK(inc[i].class_id == ref[i].class_id);
  }
  // The flat grid's lookups: every centroid of Cloud() is found under its key.
  const std::vector<VoxelGrid::Key> keys = g.Keys();
  REQUIRE(keys.size() == ref.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    const uint32_t v = g.Find(keys[i]);
    REQUIRE(v != VoxelKeyIndex::kNone);
    CHECK(g.KeyAt(v) == keys[i]);
    CHECK(g.CentroidAt(v).y == ref[i].y);
  }
  CHECK(g.Find({1000, 0, 0}) == VoxelKeyIndex::kNone);
  // SOR with context: a point far from both the batch and the map goes; a new point lying on the
  // map's surface stays although the batch alone is too small to judge it (context supplies neighbours).
  PointCloud map_plane, batch;
  for (int i = 0; i < 400; ++i) {
    ColoredPoint p;
    p.x = 0.01f * float(i % 20), p.y = 0.01f * float(i / 20), p.z = 2.0f;
    map_plane.push_back(p);
  }
  for (int i = 0; i < 9; ++i) {
    ColoredPoint p;
    p.x = 0.005f + 0.02f * float(i), p.y = 0.105f, p.z = 2.0f;
    batch.push_back(p);
  }
  ColoredPoint far;
  far.x = 0.1f, far.y = 0.1f, far.z = 2.5f;
  batch.push_back(far);
  SorOptions sor;
  sor.k = 8;
  const PointCloud kept = StatisticalOutlierRemovalWithContext(batch, map_plane, sor);
  CHECK(kept.size() == 9);
  for (const ColoredPoint& p : kept) CHECK(p.z == 2.0f);
  // Without context it is plain SOR.
  CHECK(StatisticalOutlierRemovalWithContext(map_plane, PointCloud(), sor).size() ==
        StatisticalOutlierRemoval(map_plane, sor).size());
}

TEST_CASE("dense map: incremental mode keeps accepted points and matches full mode on a clean static scene") {
  using namespace dynref;
  using namespace dynref::dense;
  const Wall scene;
  const Camera& cam = scene.cam;
  const cv::Mat& bgr = scene.bgr;
  cv::Mat depth = scene.depth.clone();
  DenseMapOptions o;
  o.pixel_stride = 8, o.keyframe_leaf_m = 0.05, o.global_leaf_m = 0.05, o.filter_every_keyframes = 2;
  o.sor.k = 8;
  DenseMapOptions inc = o;
  inc.incremental = true;
  DenseMap full_map(o), inc_map(inc);
  for (int k = 0; k < 6; ++k) {
    SE3 T = SE3::Identity();
    T.translation() = Eigen::Vector3d(0.02 * k, 0, 0);
    full_map.AddKeyframe(bgr, depth, cv::Mat(), cv::Mat(), cam, T);
    const KeyframeInsertStats st = inc_map.AddKeyframe(bgr, depth, cv::Mat(), cv::Mat(), cam, T);
    CHECK(st.map_points > 0);
  }
  full_map.Finish();
  inc_map.Finish();
  // A plane seen six times: both modes keep most of it at the same voxel resolution; the
  // incremental map keeps at least what the full one does (SOR cuts the full map's rim at every
  // filter; the incremental map's rim, seen again, touches the map and stays) and never more
  // than the unfiltered union of the views.
  DenseMapOptions raw = o;
  raw.filter_every_keyframes = 100, raw.final_filter = false;
  DenseMap raw_map(raw);
  for (int k = 0; k < 6; ++k) {
    SE3 T = SE3::Identity();
    T.translation() = Eigen::Vector3d(0.02 * k, 0, 0);
    raw_map.AddKeyframe(bgr, depth, cv::Mat(), cv::Mat(), cam, T);
  }
  const double n_full = double(full_map.cloud().size()), n_inc = double(inc_map.cloud().size());
  const double n_union = double(VoxelDownsample(raw_map.cloud(), 0.05).size());
  INFO("full " << n_full << " incremental " << n_inc << " union " << n_union);
  CHECK(n_full > 0.8 * n_union);
  CHECK(n_inc >= n_full);
  CHECK(n_inc <= n_union);
  for (const ColoredPoint& p : inc_map.cloud()) CHECK(p.z == Approx(2.0).margin(1e-3));
}

TEST_CASE("dense map: incremental filter keeps voxels the map holds, judges new ones against the map around them") {
  using namespace dynref;
  using namespace dynref::dense;
  // A fronto-parallel wall at 2 m (the first keyframe seeds the map by plain SOR, which drops the
  // wall's rim: half a neighbourhood is SOR's tail), then the same wall again plus one stray
  // point 10 cm in front of it. The wall's voxels are known to the map or touch it (the rim) and
  // join it, nothing of the map is removed again, and the stray (a new voxel 5 voxels from any
  // other, judged by SOR) goes. (A stray much farther away would inflate SOR's sigma, as in PCL.)
  const Wall scene;
  const Camera& cam = scene.cam;
  const cv::Mat& bgr = scene.bgr;
  cv::Mat depth = scene.depth.clone();
  DenseMapOptions o;
  o.pixel_stride = 4, o.keyframe_leaf_m = 0.02, o.global_leaf_m = 0.02, o.filter_every_keyframes = 1;
  o.sor.k = 8, o.incremental = true;
  DenseMap map(o);
  const KeyframeInsertStats first = map.AddKeyframe(bgr, depth, cv::Mat(), cv::Mat(), cam, SE3::Identity());
  REQUIRE(first.global_filter_ran);
  const int64_t wall = first.map_points;
  CHECK(wall > 1000);
  depth.at<float>(cam.height / 2, cam.width / 2) = 1.9f;
  const KeyframeInsertStats second = map.AddKeyframe(bgr, depth, cv::Mat(), cv::Mat(), cam, SE3::Identity());
  CHECK(first.sor_removed > 1000);
  CHECK(second.sor_removed >= 1);
  CHECK(second.sor_removed < 10);
  CHECK(second.map_points > wall + 1000);
  map.Finish();
  CHECK(static_cast<int64_t>(map.cloud().size()) == second.map_points);
  for (const ColoredPoint& p : map.cloud()) CHECK(p.z == Approx(2.0).margin(1e-3));
}
