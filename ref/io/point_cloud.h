// Point and mesh types the PLY files hold (io/ply.h): coloured 3-D points of dynref's dense
// maps (seed 001, Sec. 3.6) and triangle meshes (the static scene of a synthetic sequence).
// Plain data, here in io so that every room that reads or writes them (eval, synth, dense, ...)
// sits above it; dense/ names them dense::ColoredPoint / dense::PointCloud.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace dynref {

struct ColoredPoint {
  float x = 0, y = 0, z = 0;  // metres, world frame once appended to a map
  uint8_t r = 0, g = 0, b = 0;
  int16_t class_id = -1;      // COCO id of a recognised static object, -1 = none
};

using PointCloud = std::vector<ColoredPoint>;

// A triangle mesh (e.g. the static scene of a synthetic sequence, gt/static_scene.ply).
struct TriangleMesh {
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<uint32_t, 3>> faces;  // vertex indices, counter-clockwise seen from outside
};

}  // namespace dynref
