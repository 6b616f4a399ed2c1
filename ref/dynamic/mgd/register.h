// MGD-SLAM (seed 000) components for the MethodRegistry (configs/mgd*.yaml; every option is a
// parameter of mgd.probability, the other two stages take none and read them from the run's
// shared MGD state):
//   mgd.boxes         kBeforeInitialPose  Flag_d per feature and line sample (Sec. 3.3); initial
//                                         pose from out-of-box features (spec E10); first frame: P_init
//   mgd.probability   kBeforeFinalPose    inheritance, P_LS, P_mf, cached P_pro, fusion,
//                     (after the local-map search; after_local_map_search: false = kAfterInitialPose)
//                                         smoothing, diffusion, suppression, weights (Sec. 3.4-3.6),
//                                         for points and line samples (step 11)
//   mgd.reprojection  kOnMapUpdate        P_pro of the new keyframe's map points over 1st + 2nd
//                                         order covisible keyframes, cached per map point (Sec. 3.5)
#pragma once
#include "method/registry.h"

namespace dynref {
void RegisterMgdMethod(MethodRegistry& registry);
}  // namespace dynref
