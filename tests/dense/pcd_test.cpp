// PCD writer/reader of dense maps (PLY: tests/io/ply_test.cpp).
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "dense/pcd_io.h"
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

std::string Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// `text` with the first `from` replaced by `to`, written to path.
std::string Patched(const std::string& text, const std::string& from, const std::string& to, const std::string& path) {
  std::string s = text;
  const size_t at = s.find(from);
  REQUIRE(at != std::string::npos);
  s.replace(at, from.size(), to);
  std::ofstream(path, std::ios::binary) << s;
  return path;
}

}  // namespace

TEST_CASE("dense pcd: counts and undeclared trailing data are errors (issue 37)") {
  const std::string dir = dynref::test::ScratchDir("dense_pcd_strict");
  WritePcd(dir + "/c.pcd", Sample());
  const std::string pcd = Bytes(dir + "/c.pcd");
  CHECK(ReadPcd(dir + "/c.pcd").size() == 3);
  CHECK_THROWS_WITH(ReadPcd(Patched(pcd, "POINTS 3", "POINTS 2", dir + "/trail.pcd")),
                    Catch::Contains("trail.pcd: 16 bytes of data after the 2 points"));
  CHECK_THROWS_WITH(ReadPcd(Patched(pcd, "POINTS 3", "POINTS -5", dir + "/neg.pcd")),
                    Catch::Contains("neg.pcd:10: POINTS '-5'"));
  CHECK_THROWS_WITH(ReadPcd(Patched(pcd, "POINTS 3", "POINTS 4", dir + "/short.pcd")), Catch::Contains("truncated"));
}
