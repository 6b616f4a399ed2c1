#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "dense/ply_writer.h"
#include "test_support.h"

using namespace dynref::dense;

namespace {
PointCloud Sample() {
  PointCloud c(3);
  c[0].x = 1.5f, c[0].y = -2.25f, c[0].z = 0.1f, c[0].r = 255, c[0].g = 1, c[0].b = 2;
  c[1].x = 0, c[1].y = 0, c[1].z = 3, c[1].r = 9;
  c[2].x = 1e-7f, c[2].y = 123.456f, c[2].z = -0.5f, c[2].b = 200;
  return c;
}
void CheckSame(const PointCloud& a, const PointCloud& b) {
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
}  // namespace

TEST_CASE("dense ply: binary and ASCII round-trip exactly, header is standard") {
  const std::string dir = dynref::test::ScratchDir("dense_ply");
  WritePly(dir + "/b.ply", Sample(), PlyFormat::kBinaryLittleEndian, "dynref test\nsecond line");
  WritePly(dir + "/a.ply", Sample(), PlyFormat::kAscii);
  CheckSame(ReadPly(dir + "/b.ply"), Sample());
  CheckSame(ReadPly(dir + "/a.ply"), Sample());
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

TEST_CASE("dense ply: empty cloud and malformed input") {
  const std::string dir = dynref::test::ScratchDir("dense_ply_bad");
  WritePly(dir + "/e.ply", {});
  CHECK(ReadPly(dir + "/e.ply").empty());
  std::ofstream(dir + "/bad.ply") << "plx\n";
  CHECK_THROWS_AS(ReadPly(dir + "/bad.ply"), dynref::InputError);
  CHECK_THROWS_AS(ReadPly(dir + "/missing.ply"), dynref::InputError);
}
