// The 3-point cloud the PLY (tests/io) and PCD (tests/dense) reader/writer tests round-trip:
// a full colour, a zero point, and values that need every float digit.
#pragma once
#include "io/point_cloud.h"

namespace dynref::test {

inline PointCloud SamplePointCloud() {
  PointCloud c(3);
  c[0].x = 1.5f, c[0].y = -2.25f, c[0].z = 0.1f, c[0].r = 255, c[0].g = 1, c[0].b = 2;
  c[1].x = 0, c[1].y = 0, c[1].z = 3, c[1].r = 9;
  c[2].x = 1e-7f, c[2].y = 123.456f, c[2].z = -0.5f, c[2].b = 200;
  return c;
}

}  // namespace dynref::test
