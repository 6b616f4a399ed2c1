// epi.nerf (seed 004 Sec. 3.3.2): the transforms.json convention (a planted camera re-projects a
// planted point to its pixel through the exported matrix), DLT triangulation and its gates,
// colour sampling, and the export of an epi run end to end.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>

#include "io/ply.h"
#include "dynamic/epi/nerf_export.h"
#include "io/camera.h"
#include "io/trajectory.h"
#include "method_e2e.h"
#include "io/image_file.h"

using namespace dynref;
using namespace dynref::epi;

namespace {

SE3 Pose(double rx, double ry, double rz, const Eigen::Vector3d& t) {
  SE3 T = SE3::Identity();
  T.linear() = (Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

}  // namespace

TEST_CASE("epi nerf: a planted camera re-projects a planted point to its pixel through transforms.json") {
  const Camera cam = CameraPreset("synthetic");
  const SE3 T_cw = Pose(0.3, -0.2, 0.1, {0.4, -0.1, 1.2});
  const Eigen::Vector3d X(0.3, 0.2, 1.5);
  const Eigen::Vector2d expected = cam.Pinhole().Project(T_cw * X);
  REQUIRE(cam.Pinhole().Contains(expected.x(), expected.y()));
  const nlohmann::json j =
      nlohmann::json::parse(TransformsJson(cam, {{"images/a.png", "masks/a.png", T_cw, 7}}, "sparse_points.ply", {}).dump());
  CHECK(j["camera_model"] == "OPENCV");
  CHECK(j["w"] == cam.width);
  CHECK(j["ply_file_path"] == "sparse_points.ply");
  REQUIRE(j["frames"].size() == 1);
  CHECK(j["frames"][0]["file_path"] == "images/a.png");
  CHECK(j["frames"][0]["mask_path"] == "masks/a.png");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = j["frames"][0]["transform_matrix"][r][c].get<double>();
  CHECK(M.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)));
  // nerfstudio / instant-ngp: the camera looks down its -z axis with y up, so a point in front
  // has z < 0 and its pixel is (fx x / -z + cx, cy - fy y / -z).
  const Eigen::Vector4d gl = M.inverse() * X.homogeneous();
  REQUIRE(gl.z() < 0);
  const double u = j["fl_x"].get<double>() * gl.x() / -gl.z() + j["cx"].get<double>();
  const double v = j["cy"].get<double>() - j["fl_y"].get<double>() * gl.y() / -gl.z();
  CHECK(u == Approx(expected.x()).margin(1e-9));
  CHECK(v == Approx(expected.y()).margin(1e-9));
  // The camera centre is the matrix's translation column.
  CHECK((M.topRightCorner<3, 1>() - T_cw.inverse().translation()).norm() < 1e-12);
}

TEST_CASE("epi nerf: DLT triangulation recovers a planted point, the gates reject the bad cases") {
  const Intrinsics K = CameraPreset("synthetic").Pinhole();
  const SE3 T0 = SE3::Identity();
  const SE3 T1 = Pose(0.0, 0.05, 0.0, {-0.2, 0.0, 0.0});
  const Eigen::Vector3d X(0.1, -0.2, 2.0);
  const Eigen::Vector2d x0 = K.Project(T0 * X), x1 = K.Project(T1 * X);
  const TriangulationGates gates;
  Eigen::Vector3d out;
  REQUIRE(TriangulateDlt(K, T0, T1, x0, x1, gates, &out) == Triangulated::kOk);
  CHECK((out - X).norm() < 1e-9);
  // One pixel of noise: still accepted, within a few mm at 2 m with a 20 cm baseline.
  REQUIRE(TriangulateDlt(K, T0, T1, x0 + Eigen::Vector2d(1, 0), x1, gates, &out) == Triangulated::kOk);
  CHECK((out - X).norm() < 0.05);
  // No baseline: no parallax.
  CHECK(TriangulateDlt(K, T0, T0, x0, x0, gates, &out) == Triangulated::kParallax);
  // Rays that meet behind the cameras.
  const Eigen::Vector3d B(0.1, -0.2, -2.0);
  const Eigen::Vector2d b0 = K.Project(T0 * B), b1 = K.Project(T1 * B);
  CHECK(TriangulateDlt(K, T0, T1, b0, b1, gates, &out) == Triangulated::kBehind);
  // Rays that do not meet: 6 px off the epipolar line in the second view.
  CHECK(TriangulateDlt(K, T0, T1, x0, x1 + Eigen::Vector2d(0, 6), gates, &out) == Triangulated::kReprojection);
  TriangulationGates bad;
  bad.parallax_cos_max = 1.0;
  CHECK_THROWS_AS(bad.Check(), std::invalid_argument);
}

TEST_CASE("epi nerf: colour sampling is bilinear RGB in [0, 1] and refuses pixels outside") {
  cv::Mat bgr(4, 4, CV_8UC3, cv::Scalar(0, 0, 0));
  bgr.at<cv::Vec3b>(1, 2) = cv::Vec3b(255, 0, 0);  // blue
  Eigen::Vector3d c;
  REQUIRE(SampleRgb(bgr, 2, 1, &c));
  CHECK(c.isApprox(Eigen::Vector3d(0, 0, 1)));
  REQUIRE(SampleRgb(bgr, 2.5, 1, &c));
  CHECK(c.z() == Approx(0.5));
  CHECK(SampleRgb(bgr, 3, 3, &c));
  CHECK(!SampleRgb(bgr, 3.5, 0, &c));
  CHECK(!SampleRgb(bgr, -0.1, 0, &c));
}

TEST_CASE("epi nerf: an epi run end to end exports keyframe images, dynamic masks, points and transforms.json", "[e2e]") {
  const std::string dir = test::ScratchDir("epi_nerf_e2e");
  synth::SynthOptions so;
  so.preset = "walking_xyz", so.frames = 40, so.seed = 1, so.detections = "yolo-like";
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  test::E2eSequence seq{so, so.out + "/detections/yolo-like"};
  const std::string run = dir + "/run";
  CHECK(test::RunE2eAte(seq, "epi", run) < 0.03);
  const std::string nerf = run + "/nerf";
  std::ifstream in(nerf + "/transforms.json");
  REQUIRE(in.good());
  const nlohmann::json j = nlohmann::json::parse(in);
  // One frame per keyframe of the run, each with its image and mask, poses those of keyframes.txt.
  const TumTrajectory kfs = ReadTumTrajectory(run + "/keyframes.txt");
  REQUIRE(j["frames"].size() == kfs.poses.size());
  int masked_frames = 0;
  for (size_t i = 0; i < j["frames"].size(); ++i) {
    const nlohmann::json& f = j["frames"][i];
    const cv::Mat image = dynref::ImageRead(nerf + "/" + f["file_path"].get<std::string>(), cv::IMREAD_COLOR);
    const cv::Mat mask = dynref::ImageRead(nerf + "/" + f["mask_path"].get<std::string>(), cv::IMREAD_UNCHANGED);
    REQUIRE(!image.empty());
    REQUIRE(mask.type() == CV_8U);
    CHECK(mask.size() == image.size());
    masked_frames += cv::countNonZero(mask == 0) > 0;
    Eigen::Matrix4d M;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) M(r, c) = f["transform_matrix"][r][c].get<double>();
    CHECK((M.topRightCorner<3, 1>() - kfs.poses[i].T_wc.translation()).norm() < 1e-4);  // keyframes.txt: 4 decimals
  }
  CHECK(masked_frames > 0);  // the walkers' masks were voted dynamic in some keyframes
  const nlohmann::json& d = j["dynref"];
  const PointCloud points = ReadPly(nerf + "/" + j["ply_file_path"].get<std::string>());
  CHECK(points.size() == d["points"].get<size_t>());
  CHECK(points.size() > 20);
  CHECK(d["triangulation"]["ok"].get<int64_t>() >= static_cast<int64_t>(points.size()));
  CHECK(d["l_geo"].get<double>() > 0);
  CHECK(d["l_geo"].get<double>() < 0.1);
  // The synthetic room spans a few metres: every pseudo-point lies within it.
  for (const auto& p : points) CHECK(Eigen::Vector3f(p.x, p.y, p.z).norm() < 10.0f);
}
