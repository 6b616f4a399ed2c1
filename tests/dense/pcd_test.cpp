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

}  // namespace

TEST_CASE("dense pcd: counts and undeclared trailing data are errors (issue 37)") {
  const std::string dir = dynref::test::ScratchDir("dense_pcd_strict");
  WritePcd(dir + "/c.pcd", Sample());
  const std::string pcd = dynref::test::ReadFileBytes(dir + "/c.pcd");
  CHECK(ReadPcd(dir + "/c.pcd").size() == 3);
  CHECK_THROWS_WITH(ReadPcd(dynref::test::WritePatched(pcd, "POINTS 3", "POINTS 2", dir + "/trail.pcd")),
                    Catch::Contains("trail.pcd: 16 bytes of data after the 2 points"));
  CHECK_THROWS_WITH(ReadPcd(dynref::test::WritePatched(pcd, "POINTS 3", "POINTS -5", dir + "/neg.pcd")),
                    Catch::Contains("neg.pcd:10: POINTS '-5'"));
  CHECK_THROWS_WITH(ReadPcd(dynref::test::WritePatched(pcd, "POINTS 3", "POINTS 4", dir + "/short.pcd")), Catch::Contains("truncated"));
}
