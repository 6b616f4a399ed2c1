// Map evaluation (issue 16): exact point-to-triangle distances, and accuracy / completeness /
// ghost figures on hand-built scenes where every number is known; the CLI on a synthetic sequence.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "core/rng.h"
#include "io/ply.h"
#include "eval/map_eval.h"
#include "test_support.h"

using namespace dynref;

namespace {

// Unit square in the z = 0 plane as two triangles.
TriangleMesh Square() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

double BruteForce(const TriangleMesh& m, const Eigen::Vector3d& q) {
  double best = 1e300;
  for (const auto& f : m.faces) {
    const auto v = [&](uint32_t i) { return Eigen::Vector3d(m.vertices[i][0], m.vertices[i][1], m.vertices[i][2]); };
    // dense sampling of the triangle as an independent reference
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; i + j <= 200; ++j)
        best = std::min(best, (v(f[0]) + (v(f[1]) - v(f[0])) * (i / 200.0) + (v(f[2]) - v(f[0])) * (j / 200.0) - q).norm());
  }
  return best;
}

}  // namespace

TEST_CASE("map-eval: closest point on a triangle in each Voronoi region") {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK((ClosestPointOnTriangle({-1, -1, 0}, a, b, c) - a).norm() < 1e-12);         // vertex a
  CHECK((ClosestPointOnTriangle({2, -0.5, 0}, a, b, c) - b).norm() < 1e-12);        // vertex b
  CHECK((ClosestPointOnTriangle({0.5, -1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0, 0)).norm() < 1e-12);  // edge ab
  CHECK((ClosestPointOnTriangle({1, 1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0.5, 0)).norm() < 1e-12);   // edge bc
  CHECK((ClosestPointOnTriangle({0.2, 0.3, 2}, a, b, c) - Eigen::Vector3d(0.2, 0.3, 0)).norm() < 1e-12);  // face
}

TEST_CASE("map-eval: mesh distance equals a brute-force reference near and far from the mesh") {
  TriangleMesh m = Square();
  m.vertices.push_back({0.5f, 0.5f, 1.0f});  // a tent over the square
  m.faces.push_back({0, 1, 4});
  const MeshDistance d(m, 0.02);
  Rng rng(7, "test.map_eval");
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d q(rng.Uniform(-0.3, 1.3), rng.Uniform(-0.3, 1.3), rng.Uniform(-0.2, 0.6));
    INFO(q.transpose());
    const double ref = BruteForce(m, q);
    // exact near the mesh; beyond 10 samples (0.2 m) within one sample spacing
    CHECK(d.Distance(q) == Approx(ref).margin(ref > 0.2 ? 0.02 : 0.006));
    CHECK(d.Distance(q) >= ref - 0.006);
  }
}

TEST_CASE("map-eval: accuracy, completeness and ghosts of a hand-built map", "[cli]") {
  const TriangleMesh plane = Square();
  PointCloud observed, movers;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) observed.push_back({0.05f + 0.1f * i, 0.05f + 0.1f * j, 0.f});
  movers.push_back({0.5f, 0.5f, 0.5f});  // a person stood 0.5 m above the middle
  std::vector<Eigen::Vector3d> map;
  for (int i = 0; i < 5; ++i)  // the left half of the plane, 1 cm above it
    for (int j = 0; j < 10; ++j) map.emplace_back(0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.01);
  map.emplace_back(0.5, 0.5, 0.48);  // ghost: 2 cm from the mover, 48 cm from the plane
  map.emplace_back(0.5, 0.5, 0.30);  // far from both: inaccurate, no ghost
  const MapEvalResult r = EvaluateMap(map, plane, observed, movers, MapEvalOptions{});
  CHECK(r.map_points == 52);
  CHECK(r.ghosts == 1);
  CHECK(r.ghost_fraction == Approx(1.0 / 52));
  CHECK(r.observed == 100);
  CHECK(r.observed_covered == 50);  // right-half voxels are >= 5.1 cm from the nearest map point
  CHECK(r.completeness == Approx(0.5));
  CHECK(r.accuracy.median == Approx(0.01).margin(1e-6));
  // Beyond 10 sample spacings (0.2 m) the distance is the nearest sample's: within 2 cm, never below.
  CHECK(r.accuracy.max >= 0.48 - 1e-6);
  CHECK(r.accuracy.max <= 0.50);
  CHECK(r.accuracy.mean >= (50 * 0.01 + 0.48 + 0.30) / 52 - 1e-6);
  CHECK(r.accuracy.mean <= (50 * 0.01 + 0.50 + 0.32) / 52);
}

TEST_CASE("map-eval: PLY mesh round trip and bad mesh files") {
  const std::string dir = test::ScratchDir("ply_mesh");
  const TriangleMesh m = Square();
  WritePlyMesh(dir + "/m.ply", m, "a comment");
  const TriangleMesh back = ReadPlyMesh(dir + "/m.ply");
  CHECK(back.vertices == m.vertices);
  CHECK(back.faces == m.faces);
  CHECK_THROWS_WITH(ReadPlyMesh(test::WriteText(dir + "/x.ply", "ply\nformat ascii 1.0\nend_header\n")),
                    Catch::Contains("x.ply") && Catch::Contains("not a dynref triangle-mesh PLY"));
}

TEST_CASE("map-eval CLI: the synthetic truth scores itself perfectly, a mover cloud is all ghosts", "[cli]") {
  const std::string dir = test::ScratchDir("map_eval_cli");
  REQUIRE(test::RunDynref("synth --preset walking_xyz --frames 5 --seed 1 --out " + dir + "/seq").exit_code == 0);
  for (const char* f : {"static_scene.ply", "static_observed.ply", "movers_observed.ply"})
    CHECK(test::FileExists(dir + "/seq/gt/" + std::string(f)));
  const std::string gt_traj = " --trajectory " + dir + "/seq/groundtruth.txt";
  const test::CommandResult self =
      test::RunDynref("map-eval " + dir + "/seq/gt/static_observed.ply --gt " + dir + "/seq" + gt_traj + " --json " + dir + "/s.json");
  INFO(self.output);
  REQUIRE(self.exit_code == 0);
  CHECK(self.output.find("completeness   100.0 %") != std::string::npos);
  CHECK(self.output.find("ghosts         0 points") != std::string::npos);
  CHECK(test::ReadFileBytes(dir + "/s.json").find("\"ghost_fraction\": 0.0") != std::string::npos);
  const test::CommandResult movers =
      test::RunDynref("map-eval " + dir + "/seq/gt/movers_observed.ply --gt " + dir + "/seq" + gt_traj);
  INFO(movers.output);
  REQUIRE(movers.exit_code == 0);
  CHECK(movers.output.find("ghosts         0 points") == std::string::npos);
  test::ExpectBadInput("map-eval " + dir + "/seq/gt/static_observed.ply --gt " + dir, "static_scene.ply: missing");
  test::ExpectBadInput("map-eval " + dir + "/seq/groundtruth.txt --gt " + dir + "/seq", ".ply or .pcd");
}

TEST_CASE("map-eval CLI: an empty map, a NaN point, undeclared vertices and a negative count exit 2 naming the file (issue 37)", "[cli]") {
  const std::string dir = test::ScratchDir("map_eval_cli_bad_maps");
  REQUIRE(test::RunDynref("synth --preset walking_xyz --frames 3 --seed 1 --out " + dir + "/seq").exit_code == 0);
  const std::string tail = " --gt " + dir + "/seq --trajectory " + dir + "/seq/groundtruth.txt";
  // 0 vertices: was "accuracy 0.0000".
  WritePly(dir + "/empty.ply", {});
  test::ExpectBadInput("map-eval " + dir + "/empty.ply" + tail, "empty.ply: the map has 0 points");
  // A NaN point: was "mean nan".
  PointCloud cloud(120);
  for (size_t i = 0; i < cloud.size(); ++i) cloud[i].x = 0.01f * float(i);
  PointCloud with_nan = cloud;
  with_nan[7].z = std::nanf("");
  WritePly(dir + "/nan.ply", with_nan);
  test::ExpectBadInput("map-eval " + dir + "/nan.ply" + tail, "nan.ply: vertex 7 has a non-finite coordinate");
  WritePly(dir + "/nan_ascii.ply", with_nan, PlyFormat::kAscii);
  test::ExpectBadInput("map-eval " + dir + "/nan_ascii.ply" + tail, "nan_ascii.ply:18: vertex 7 has a non-finite");
  // The header says 100, the file holds 120: was read as 100 points.
  WritePly(dir + "/ok.ply", cloud);
  std::string bytes = test::ReadFileBytes(dir + "/ok.ply");
  const auto patch = [&](const std::string& to, const std::string& name) {
    std::string s = bytes;
    s.replace(s.find("element vertex 120"), 18, to);
    std::ofstream(dir + "/" + name, std::ios::binary) << s;
    return dir + "/" + name;
  };
  test::ExpectBadInput("map-eval " + patch("element vertex 100", "trail.ply") + tail,
                       "trail.ply: 300 bytes of data after the 100 vertices (line 3)");
  // element vertex -5: was a raw assertion.
  test::ExpectBadInput("map-eval " + patch("element vertex -5", "neg.ply") + tail, "neg.ply:3: vertex count '-5'");
  // The same map with the right count is evaluated.
  CHECK(test::RunDynref("map-eval " + dir + "/ok.ply" + tail).exit_code == 0);
}
