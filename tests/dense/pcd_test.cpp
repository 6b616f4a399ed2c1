// PCD writer/reader of dense maps (PLY: tests/io/ply_test.cpp).
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "dense/pcd_io.h"
#include "io/point_cloud_sample.h"
#include "test_support.h"

using namespace dynref::dense;

TEST_CASE("dense pcd: counts and undeclared trailing data are errors (issue 37)") {
  const std::string dir = dynref::test::ScratchDir("dense_pcd_strict");
  WritePcd(dir + "/c.pcd", dynref::test::SamplePointCloud());
  const std::string pcd = dynref::test::ReadFileBytes(dir + "/c.pcd");
  CHECK(ReadPcd(dir + "/c.pcd").size() == 3);
  CHECK_THROWS_WITH(ReadPcd(dynref::test::WritePatched(pcd, "POINTS 3", "POINTS 2", dir + "/trail.pcd")),
                    Catch::Contains("trail.pcd: 16 bytes of data after the 2 points"));
  CHECK_THROWS_WITH(ReadPcd(dynref::test::WritePatched(pcd, "POINTS 3", "POINTS -5", dir + "/neg.pcd")),
                    Catch::Contains("neg.pcd:10: POINTS '-5'"));
  CHECK_THROWS_WITH(ReadPcd(dynref::test::WritePatched(pcd, "POINTS 3", "POINTS 4", dir + "/short.pcd")), Catch::Contains("truncated"));
}
