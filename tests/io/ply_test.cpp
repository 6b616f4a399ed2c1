// PLY point-cloud and triangle-mesh writer/reader (io/ply.h).
#include <catch2/catch.hpp>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "io/ply.h"
#include "io/point_cloud_sample.h"
#include "test_support.h"

using namespace dynref;

namespace {
void PlyCheckSame(const PointCloud& a, const PointCloud& b) {
  REQUIRE(a.size() == b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].x == b[i].x);
    CHECK(a[i].y == b[i].y);
    CHECK(a[i].z == b[i].z);
    CHECK(a[i].r == b[i].r);
    CHECK(a[i].g == b[i].g);
    CHECK(a[i].b == b[i].b);
  }
}


// ReadPly of `text` with its first `from` replaced by `to`, written as dir/name.
PointCloud PlyReadPatched(const std::string& text, const std::string& from, const std::string& to,
                          const std::string& dir, const std::string& name) {
  return ReadPly(dynref::test::WritePatched(text, from, to, dir + "/" + name));
}
}  // namespace

TEST_CASE("io ply: binary and ASCII round-trip exactly, header is standard") {
  const std::string dir = dynref::test::ScratchDir("io_ply");
  WritePly(dir + "/b.ply", dynref::test::SamplePointCloud(), PlyFormat::kBinaryLittleEndian, "dynref test\nsecond line");
  WritePly(dir + "/a.ply", dynref::test::SamplePointCloud(), PlyFormat::kAscii);
  PlyCheckSame(ReadPly(dir + "/b.ply"), dynref::test::SamplePointCloud());
  PlyCheckSame(ReadPly(dir + "/a.ply"), dynref::test::SamplePointCloud());
  std::ifstream in(dir + "/b.ply", std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string s = ss.str();
  CHECK(s.rfind("ply\nformat binary_little_endian 1.0\ncomment dynref test\ncomment second line\n"
                "element vertex 3\n", 0) == 0);
  const size_t header_end = s.find("end_header\n") + 11;
  CHECK(s.size() - header_end == 3 * 15);
  // Byte order: 1.5f = 0x3fc00000 little endian.
  CHECK(static_cast<unsigned char>(s[header_end + 3]) == 0x3f);
  CHECK(static_cast<unsigned char>(s[header_end + 2]) == 0xc0);
}

TEST_CASE("io ply: empty cloud and malformed input") {
  const std::string dir = dynref::test::ScratchDir("io_ply_bad");
  WritePly(dir + "/e.ply", {});
  CHECK(ReadPly(dir + "/e.ply").empty());
  std::ofstream(dir + "/bad.ply") << "plx\n";
  CHECK_THROWS_AS(ReadPly(dir + "/bad.ply"), dynref::InputError);
  CHECK_THROWS_AS(ReadPly(dir + "/missing.ply"), dynref::InputError);
}

TEST_CASE("io ply: counts, undeclared trailing data and non-finite points are errors naming file and line (issue 37)") {
  const std::string dir = dynref::test::ScratchDir("io_ply_strict");
  PointCloud many(150);
  for (size_t i = 0; i < many.size(); ++i) many[i].x = float(i);
  WritePly(dir + "/many.ply", many);
  const std::string bin = dynref::test::ReadFileBytes(dir + "/many.ply");
  // The header says 100, the file holds 150: no longer reads 100 silently.
  CHECK_THROWS_WITH(PlyReadPatched(bin, "element vertex 150", "element vertex 100", dir, "trail.ply"),
                    Catch::Contains("trail.ply: 750 bytes of data after the 100 vertices (line 3)"));
  CHECK_THROWS_WITH(PlyReadPatched(bin, "element vertex 150", "element vertex 200", dir, "short.ply"),
                    Catch::Contains("short.ply: truncated"));
  // A negative or non-decimal count: file:line, not a wrapped-around size (bad_alloc / assertion).
  CHECK_THROWS_WITH(PlyReadPatched(bin, "element vertex 150", "element vertex -5", dir, "neg.ply"),
                    Catch::Contains("neg.ply:3: vertex count '-5' is not a whole number >= 0"));
  CHECK_THROWS_WITH(PlyReadPatched(bin, "element vertex 150", "element vertex 1e9", dir, "exp.ply"),
                    Catch::Contains("exp.ply:3:"));
  CHECK_THROWS_WITH(PlyReadPatched(bin, "element vertex 150", "element vertex 99999999999999", dir, "huge.ply"),
                    Catch::Contains("huge.ply: truncated"));
  // NaN: binary names the vertex, ASCII the line (header: 10 lines, vertex 1 on line 12).
  PointCloud bad = dynref::test::SamplePointCloud();
  bad[1].y = std::numeric_limits<float>::quiet_NaN();
  WritePly(dir + "/nan.ply", bad);
  CHECK_THROWS_WITH(ReadPly(dir + "/nan.ply"), Catch::Contains("nan.ply: vertex 1 has a non-finite coordinate"));
  WritePly(dir + "/nan_ascii.ply", bad, PlyFormat::kAscii);
  CHECK_THROWS_WITH(ReadPly(dir + "/nan_ascii.ply"), Catch::Contains("nan_ascii.ply:12: vertex 1 has a non-finite coordinate"));
  bad[1].y = std::numeric_limits<float>::infinity();
  WritePly(dir + "/inf.ply", bad);
  CHECK_THROWS_WITH(ReadPly(dir + "/inf.ply"), Catch::Contains("non-finite"));
  // ASCII: a line beyond the declared count, a short file, a bad colour.
  WritePly(dir + "/a.ply", dynref::test::SamplePointCloud(), PlyFormat::kAscii);
  const std::string ascii = dynref::test::ReadFileBytes(dir + "/a.ply");
  CHECK_THROWS_WITH(PlyReadPatched(ascii, "element vertex 3", "element vertex 2", dir, "a_trail.ply"),
                    Catch::Contains("a_trail.ply:13: data after the 2 vertices (line 3)"));
  CHECK_THROWS_WITH(PlyReadPatched(ascii, "element vertex 3", "element vertex 4", dir, "a_short.ply"),
                    Catch::Contains("a_short.ply"));
  CHECK_THROWS_WITH(PlyReadPatched(ascii, " 255 1 2\n", " 256 1 2\n", dir, "a_colour.ply"),
                    Catch::Contains("a_colour.ply:11: colour '256'"));
  CHECK_THROWS_WITH(PlyReadPatched(ascii, "element vertex 3", "element vertex -5", dir, "a_neg.ply"),
                    Catch::Contains("a_neg.ply:3:"));
  // What WritePly writes still reads back (blank trailing lines in ASCII are fine).
  PlyCheckSame(PlyReadPatched(ascii, "end_header\n", "end_header\n", dir, "a_same.ply"), dynref::test::SamplePointCloud());
  std::ofstream(dir + "/a_same.ply", std::ios::app) << "\n\n";
  PlyCheckSame(ReadPly(dir + "/a_same.ply"), dynref::test::SamplePointCloud());
  CHECK(ReadPly(dir + "/many.ply").size() == 150);
}

TEST_CASE("io ply mesh: counts and undeclared trailing data are errors (issue 37)") {
  const std::string dir = dynref::test::ScratchDir("io_ply_mesh_strict");
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}};
  WritePlyMesh(dir + "/m.ply", m);
  const std::string mesh = dynref::test::ReadFileBytes(dir + "/m.ply");
  CHECK(ReadPlyMesh(dir + "/m.ply").faces.size() == 1);
  CHECK_THROWS_WITH(ReadPlyMesh(dynref::test::WritePatched(mesh, "element vertex 3", "element vertex 2", dir + "/m_trail.ply")),
                    Catch::Contains("m_trail.ply: 12 bytes of data after the 2 vertices and 1 faces"));
  CHECK_THROWS_WITH(ReadPlyMesh(dynref::test::WritePatched(mesh, "element face 1", "element face -5", dir + "/m_neg.ply")),
                    Catch::Contains("m_neg.ply:7: face count '-5'"));
}
