// Semantic mapping (seed 002) components for the MethodRegistry:
//   semantic.mask  stage, kAfterExtraction  class partition (Table 1), interaction test
//                                           (Sec. 3.2), dynamic mask, keypoint removal
//   semantic.map   map module               keyframe clouds (Sec. 3.3.1) registered with the
//                                           final poses at the end, SOR, voxel grid, OctoMap
//                                           octree, 2-D occupancy grid (Sec. 3.3.2-3.3.5)
#pragma once
#include "method/registry.h"

namespace dynref {
void RegisterSemanticMethod(MethodRegistry& registry);
}  // namespace dynref
