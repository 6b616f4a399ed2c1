// Loop closing's global BA over the backbone's line and plane landmarks (loop/global_ba.h): a planted
// map of three keyframes that see 24 points and one plane without noise. Points only, a drifted
// plane stays where it was; with the structure tracker the plane joins the problem (the method's
// exclusions and weights still apply to the points) and comes back to the truth. After a loop
// correction, lines and planes follow the keyframe that created them.
#include <catch2/catch.hpp>
#include <cmath>

#include "io/camera.h"
#include "loop/global_ba.h"
#include "loop/yaw_pose.h"
#include "structure/structure_tracker.h"
#include "trace/trace_writer.h"

using namespace dynref;

namespace {

// Wall z = 3 in the world (n = (0, 0, -1), d = 3: n^T X + d = 0 with n towards the cameras).
const Eigen::Vector3d kGbaWallN(0, 0, -1);
constexpr double kGbaWallD = 3.0;

struct GbaScene {
  Camera cam = CameraPreset("synthetic");
  Map map;
  std::vector<SE3> truth;
  int64_t plane = -1, line = -1;
};

// Keyframe k at the true pose, features = projections of the points, one plane observation.
void GbaAddKeyFrame(GbaScene& s, const SE3& T_cw, const std::vector<Eigen::Vector3d>& X) {
  const Intrinsics K = s.cam.Pinhole();
  auto owned = std::make_unique<KeyFrame>();
  owned->T_cw = T_cw;
  Frame& f = owned->frame;
  f.pyramid = ScalePyramid::Make(8, 1.2);
  for (const Eigen::Vector3d& Xw : X) {
    const Eigen::Vector3d c = T_cw * Xw;
    const float u = static_cast<float>(K.fx * c.x() / c.z() + K.cx), v = static_cast<float>(K.fy * c.y() / c.z() + K.cy);
    f.keys_un.emplace_back(cv::Point2f(u, v), 31.f, -1.f, 0.f, 0);
    f.u_right.push_back(static_cast<float>(u - K.bf / c.z()));
  }
  f.keys = f.keys_un;
  f.structure.planes.resize(1);
  f.structure.planes[0].n = T_cw.linear() * kGbaWallN;
  f.structure.planes[0].d = kGbaWallD - f.structure.planes[0].n.dot(T_cw.translation());
  f.structure.Reset(0, 1);
  owned->map_point_ids.assign(X.size(), -1);
  s.map.AddKeyFrame(std::move(owned));
  s.truth.push_back(T_cw);
}

GbaScene GbaMakeScene() {
  GbaScene s;
  std::vector<Eigen::Vector3d> X;
  for (int i = 0; i < 24; ++i) X.emplace_back(-0.9 + 0.08 * i, -0.5 + 0.045 * (i % 5) * (i % 3), 2.4 + 0.25 * (i % 4));
  GbaAddKeyFrame(s, test::YawPose(0.0, {0, 0, 0}), X);
  GbaAddKeyFrame(s, test::YawPose(0.05, {-0.10, 0.01, 0}), X);
  GbaAddKeyFrame(s, test::YawPose(-0.04, {0.12, -0.02, 0.05}), X);
  for (size_t i = 0; i < X.size(); ++i) {
    const int64_t id = s.map.NewMapPoint(X[i], 0, 0)->id;
    for (int64_t k = 0; k < 3; ++k) s.map.AddObservation(id, k, static_cast<int>(i));
  }
  s.plane = s.map.NewMapPlane(kGbaWallN, kGbaWallD, 0, 0)->id;
  for (int64_t k = 0; k < 3; ++k) s.map.AddPlaneObservation(s.plane, k, 0);
  s.line = s.map.NewMapLine({-0.5, 0.2, 3.0}, {0.5, 0.2, 3.0}, cv::Mat::zeros(1, 32, CV_8U), 1, 1)->id;
  return s;
}

structure::StructureOptions GbaStructureOptions() {
  structure::StructureOptions o;
  o.lines = true;
  o.planes = true;
  return o;
}

}  // namespace

TEST_CASE("loop global BA: planes join the problem, the method's exclusions and weights stay, a drifted plane is pulled back") {
  GbaScene s = GbaMakeScene();
  trace::TraceWriter tr("", trace::Level::kOff, trace::RunHeader{});
  const structure::StructureTracker st(s.cam, GbaStructureOptions(), tr);
  // The method excluded feature 3 of keyframe 1 and down-weighted feature 4 there.
  s.map.kf(1)->frame.Exclude(3, "test", "dynamic");
  s.map.kf(1)->frame.SetWeight(4, 0.25);
  const loop::GlobalBAProblem points_only = loop::BuildGlobalBA(s.map, nullptr);
  const loop::GlobalBAProblem joint = loop::BuildGlobalBA(s.map, &st);
  REQUIRE(joint.keyframes.size() == 3);
  CHECK(joint.keyframes[0].fixed);
  CHECK_FALSE(joint.keyframes[1].fixed);
  CHECK(joint.observations.size() == 3 * 24 - 1);
  CHECK(points_only.observations.size() == joint.observations.size());
  bool weighted = false;
  for (const optim::BAObservation& o : joint.observations) {
    CHECK_FALSE((o.kf_id == 1 && o.trace_feature == 3));
    if (o.kf_id == 1 && o.trace_feature == 4) weighted = o.weight == 0.25;
  }
  CHECK(weighted);
  CHECK(points_only.structure.planes.empty());
  REQUIRE(joint.structure.planes.size() == 1);
  CHECK(joint.structure.plane_observations.size() == 3);

  // The plane drifted by 4 cm (as a map drifts before a loop): the joint global BA brings it back,
  // the points-only one leaves it.
  s.map.good_plane(s.plane)->d = kGbaWallD + 0.04;
  optim::LocalBAOptions ba;
  ba.iterations_robust = 10, ba.iterations_refine = 0;  // loop_closer.cpp's global BA settings
  for (const bool with_structure : {false, true}) {
    const loop::GlobalBAProblem p = loop::BuildGlobalBA(s.map, with_structure ? &st : nullptr);
    const optim::LocalBAResult r = optim::LocalBundleAdjust(s.cam.Pinhole(), p.keyframes, p.points, p.observations,
                                                            with_structure ? &p.structure : nullptr, ba, nullptr, "");
    loop::ApplyGlobalBA(s.map, p, r, with_structure ? &st : nullptr);
    const double err = std::fabs(s.map.good_plane(s.plane)->d - kGbaWallD);
    if (with_structure) {
      CHECK(err < 1e-3);
    } else {
      CHECK(err == Approx(0.04).margin(1e-12));
    }
    for (int k = 1; k < 3; ++k)
      CHECK((s.map.kf(k)->CameraCentre() - s.truth[static_cast<size_t>(k)].inverse().translation()).norm() < 1e-3);
  }
  // No observation is erased by the global BA.
  CHECK(s.map.good_plane(s.plane)->observations.size() == 3);
}

TEST_CASE("loop correction: lines and planes follow the keyframe that created them") {
  GbaScene s = GbaMakeScene();
  std::map<int64_t, SE3> before;
  for (const auto& [id, k] : s.map.keyframes) before[id] = k->T_cw;
  // Keyframe 0 created the plane, keyframe 1 the line; the correction moves keyframe 1 only.
  const SE3 corr = test::YawPose(0.1, {0.05, -0.02, 0.3});
  s.map.kf(1)->T_cw = s.map.kf(1)->T_cw * corr;
  const Eigen::Vector3d Ps_cam = before[1] * s.map.good_line(s.line)->P_s, Pe_cam = before[1] * s.map.good_line(s.line)->P_e;
  loop::MoveStructureWithKeyFrames(s.map, before);
  // The line stays where keyframe 1 saw it; the plane of the unmoved keyframe 0 stays put.
  CHECK((s.map.kf(1)->T_cw * s.map.good_line(s.line)->P_s - Ps_cam).norm() < 1e-12);
  CHECK((s.map.kf(1)->T_cw * s.map.good_line(s.line)->P_e - Pe_cam).norm() < 1e-12);
  CHECK((s.map.good_plane(s.plane)->n - kGbaWallN).norm() < 1e-12);
  CHECK(s.map.good_plane(s.plane)->d == Approx(kGbaWallD).margin(1e-12));
  // Now keyframe 0 moves: the plane keeps its parameters in keyframe 0's camera frame.
  before.clear();
  for (const auto& [id, k] : s.map.keyframes) before[id] = k->T_cw;
  s.map.kf(0)->T_cw = corr * s.map.kf(0)->T_cw;
  loop::MoveStructureWithKeyFrames(s.map, before);
  const MapPlane& P = *s.map.good_plane(s.plane);
  const Eigen::Vector3d n_c = s.map.kf(0)->T_cw.linear() * P.n;
  const double d_c = P.d - n_c.dot(s.map.kf(0)->T_cw.translation());
  CHECK((n_c - kGbaWallN).norm() < 1e-12);
  CHECK(d_c == Approx(kGbaWallD).margin(1e-12));
}
