// Coloured 3-D points of dynref's dense maps (seed 001, Sec. 3.6).
#pragma once
#include <cstdint>
#include <vector>

namespace dynref::dense {

struct ColoredPoint {
  float x = 0, y = 0, z = 0;  // metres, world frame once appended to a map
  uint8_t r = 0, g = 0, b = 0;
  int16_t class_id = -1;      // COCO id of a recognised static object, -1 = none
};

using PointCloud = std::vector<ColoredPoint>;

}  // namespace dynref::dense
