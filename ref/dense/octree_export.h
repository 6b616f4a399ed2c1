// Semantic octree of a coloured cloud with OctoMap (liboctomap, Debian): an octomap::ColorOcTree
// of leaf `resolution_m` in which every cloud point marks its leaf occupied and integrates its
// colour; written as `.ot` (full ColorOcTree, opens in octovis) and `.bt` (binary occupancy
// OcTree, the compact ROS octomap_server format). seed 002 Sec. 3.3.4 describes its own
// recursive split; OctoMap's is the same tree with occupancy instead of raw counts (spec 002 (c)).
#pragma once
#include <cstdint>
#include <string>

#include "dense/point_cloud.h"

namespace dynref::dense {

struct OctreeStats {
  uint64_t leaf_nodes = 0, inner_nodes = 0, occupied_leaves = 0;
  unsigned depth = 0;
};

// Writes ot_path (ColorOcTree) and bt_path (OcTree binary) atomically; returns node counts.
OctreeStats WriteOctrees(const PointCloud& cloud, double resolution_m, const std::string& ot_path,
                         const std::string& bt_path);

}  // namespace dynref::dense
