// The 2-D occupancy grid of seed 002 (Sec. 3.3.5): a floor plane fitted to the cloud (RANSAC on
// dynref::Rng; spec 002 (c): the paper's "TF transform" is not stated), the cloud rotated so the
// floor normal is +z, a height pass-through [h_min, h_max] above the floor, projection onto
// cells of side c; a cell is occupied iff it receives a point. Written as a ROS map_server map:
// an 8-bit PGM (occupied 0, free 254, row 0 = largest y) and its YAML (image, resolution,
// origin, negate, occupied_thresh, free_thresh).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "dense/point_cloud.h"

namespace dynref::dense {

struct FloorOptions {
  Eigen::Vector3d up_hint = Eigen::Vector3d(0, -1, 0);  // world = first camera: y points down
  double max_tilt_deg = 30;      // candidate normals within this angle of up_hint
  double inlier_m = 0.02;        // point-to-plane distance of an inlier
  double max_below_fraction = 0.05;  // the floor has (almost) nothing below it
  double low_fraction = 0.3;     // hypotheses from the lowest 30 % of the points along up_hint
  int iterations = 1000;
  int max_scored = 50000;        // hypotheses scored on at most this many points (every k-th)
  uint64_t seed = 1;
};

struct FloorPlane {
  bool found = false;
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();  // unit, towards up_hint
  double d = 0;                                  // n . p + d = height above the floor
  int inliers = 0;
};

FloorPlane FitFloor(const PointCloud& cloud, const FloorOptions& options);

struct GridOptions {
  double cell_m = 0.05;
  double h_min_m = 0.1, h_max_m = 1.8;
};

struct OccupancyGrid {
  int width = 0, height = 0;
  double cell_m = 0.05;
  double origin_x = 0, origin_y = 0;  // floor-frame coordinates of cell (0, 0)'s lower-left corner
  std::vector<uint8_t> occupied;      // row-major, row 0 = lowest y
  int64_t occupied_cells = 0, points_used = 0;
};

// Rotates the cloud into the floor frame (R n = +z) and grids the points with height in
// [h_min, h_max]. An empty grid (no point in the band) has width = height = 0.
OccupancyGrid BuildOccupancyGrid(const PointCloud& cloud, const FloorPlane& floor, const GridOptions& options);
// Writes PGM + YAML atomically (the YAML names the PGM by file name).
void WriteMapServer(const OccupancyGrid& grid, const std::string& pgm_path, const std::string& yaml_path);

}  // namespace dynref::dense
