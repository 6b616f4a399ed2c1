// SGDO-SLAM (seed 001) stages for the pipeline's StageRegistry:
//   sgdo.mask      kAfterExtraction   dynamic mask M (Sec. 3.2); (S): reject keypoints in M
//   sgdo.coarse    kBeforeInitialPose LK + 7-point RANSAC F + epipolar distance (Sec. 3.3)
//   sgdo.depth     kAfterInitialPose  depth consistency eps, rejection |eps| > eta, weights (3.4-3.5)
//   sgdo.densemap  kOnKeyFrameCreated dense static map, PLY at the end (Sec. 3.6)
#pragma once
#include "pipeline/stage.h"

namespace dynref {
void RegisterSgdoStages(StageRegistry& registry);
}  // namespace dynref
