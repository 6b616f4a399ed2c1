// The ORBmatcher equivalents on planted data: brute-force keyframe-to-frame matching (distance
// threshold, ratio test, exclusion) and the motion-model projection search.
#include <catch2/catch.hpp>

#include "core/rng.h"
#include "tracking/matcher.h"

using namespace dynref;

namespace {

const Camera& Cam() {
  static const Camera c = CameraPreset("synthetic");
  return c;
}

cv::Mat RandomDescriptors(int n, uint64_t seed) {
  Rng rng(seed, "test.descriptors");
  cv::Mat d(n, 32, CV_8U);
  for (int i = 0; i < n; ++i)
    for (int b = 0; b < 32; ++b) d.at<uint8_t>(i, b) = static_cast<uint8_t>(rng.UniformInt(0, 255));
  return d;
}

// A frame with keypoints at `px` (octave 0, angle 0), the given descriptors, depth 2 m everywhere.
Frame MakeFrame(const std::vector<cv::Point2f>& px, const cv::Mat& desc, int index) {
  Frame f;
  f.index = index;
  for (const auto& p : px) f.keys.emplace_back(p, 7.f, 0.f, 0.f, 0);
  f.descriptors = desc.clone();
  f.depth_m = cv::Mat(Cam().height, Cam().width, CV_32F, cv::Scalar(2.0f));
  f.pyramid = ScalePyramid::Make(8, 1.2);
  f.FinishFeatures(Cam());
  return f;
}

}  // namespace

TEST_CASE("matcher: brute force finds the planted keyframe matches, honours exclusion and thresholds") {
  const int n = 40;
  const cv::Mat desc = RandomDescriptors(n, 1);
  std::vector<cv::Point2f> px;
  for (int i = 0; i < n; ++i) px.emplace_back(20.f + 15.f * i, 100.f + 5.f * (i % 7));
  Map map;
  auto kf_owned = std::make_unique<KeyFrame>();
  kf_owned->frame = MakeFrame(px, desc, 0);
  kf_owned->map_point_ids.assign(n, -1);
  KeyFrame* kf = map.AddKeyFrame(std::move(kf_owned));
  for (int i = 0; i < n; ++i) map.AddObservation(map.NewMapPoint(Eigen::Vector3d(0.05 * i, 0, 2), kf->id, 0)->id, kf->id, i);
  // Current frame: the keyframe's features in reverse order with 3 bits flipped each, plus
  // feature 40 = a copy of keyframe feature 5 with 60 bits flipped (beyond TH_LOW = 50).
  cv::Mat cur_desc(n + 1, 32, CV_8U);
  std::vector<cv::Point2f> cur_px;
  for (int j = 0; j < n; ++j) {
    desc.row(n - 1 - j).copyTo(cur_desc.row(j));
    cur_desc.at<uint8_t>(j, 0) ^= 0x07;
    cur_px.push_back(px[n - 1 - j]);
  }
  desc.row(5).copyTo(cur_desc.row(n));
  for (int b = 0; b < 8; ++b) cur_desc.at<uint8_t>(n, b + 10) ^= 0xFF;  // 64 bits
  cur_px.emplace_back(300.f, 300.f);
  Frame cur = MakeFrame(cur_px, cur_desc, 1);
  cur.Exclude(3, "test", "excluded");  // keyframe feature 36: never matched
  const int matches = tracking::SearchByBruteForce(*kf, cur, map, 0.75f, false);
  CHECK(matches == n - 1);
  for (int j = 0; j < n; ++j) {
    INFO("current feature " << j);
    if (j == 3) CHECK(cur.map_point_ids[j] == -1);
    else CHECK(cur.map_point_ids[j] == kf->map_point_ids[n - 1 - j]);
  }
  CHECK(cur.map_point_ids[n] == -1);  // 64 bits from its keyframe twin
}

TEST_CASE("matcher: the motion-model search projects the last frame's points to their pixels") {
  // Last frame at the origin, 30 points 2 m ahead; the current camera moved 5 cm right, so every
  // point appears fx * 0.05 / 2 = 13.4 px to the left.
  const int n = 30;
  const cv::Mat desc = RandomDescriptors(n, 2);
  Map map;
  std::vector<cv::Point2f> last_px, cur_px;
  std::vector<int64_t> ids;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d X(-0.6 + 0.04 * i, -0.2 + 0.013 * (i % 5), 2.0);
    ids.push_back(map.NewMapPoint(X, 0, 0)->id);
    map.mp(ids.back())->descriptor = desc.row(i).clone();
    const Eigen::Vector2d a = tracking::ProjectPinhole(Cam(), X);
    const Eigen::Vector2d b = tracking::ProjectPinhole(Cam(), X - Eigen::Vector3d(0.05, 0, 0));
    last_px.emplace_back(float(a.x()), float(a.y()));
    cur_px.emplace_back(float(b.x()), float(b.y()));
  }
  Frame last = MakeFrame(last_px, desc, 0);
  last.map_point_ids = ids;
  last.has_pose = true;
  Frame cur = MakeFrame(cur_px, desc, 1);
  cur.T_cw = SE3::Identity();
  cur.T_cw.translation() = Eigen::Vector3d(-0.05, 0, 0);
  cur.has_pose = true;
  for (auto& id : ids) {
    MapPoint* p = map.mp(id);
    p->normal = Eigen::Vector3d(0, 0, 1);
    p->min_distance = 0.5f, p->max_distance = 5.f;
  }
  const int matches = tracking::SearchByProjectionLastFrame(cur, last, map, 7);
  CHECK(matches == n);
  for (int i = 0; i < n; ++i) CHECK(cur.map_point_ids[i] == ids[i]);
  // Without the motion (current pose = last pose) the points are searched 13 px off: a window of
  // 7 px (scaled by the octave) finds none of them.
  Frame still = MakeFrame(cur_px, desc, 2);
  still.has_pose = true;
  CHECK(tracking::SearchByProjectionLastFrame(still, last, map, 7) == 0);
}
