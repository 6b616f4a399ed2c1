// SGDO-SLAM (seed 001) components for the MethodRegistry:
//   sgdo.mask      stage, kAfterExtraction   dynamic mask M (Sec. 3.2); (S): reject keypoints in M
//   sgdo.coarse    stage, kBeforeInitialPose LK + 7-point RANSAC F + epipolar distance (Sec. 3.3)
//   sgdo.depth     stage, kAfterInitialPose  depth consistency eps, rejection |eps| > eta, weights (3.4-3.5)
//   sgdo.densemap  map module                dense static map, PLY at the end of the run (Sec. 3.6)
#pragma once
#include "method/registry.h"

namespace dynref {
void RegisterSgdoMethod(MethodRegistry& registry);
}  // namespace dynref
