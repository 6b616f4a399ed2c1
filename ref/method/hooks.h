// The hooks at which a method's stages run, in per-frame order (issue 5, issue 12):
//   load rgb/depth/detections -> kBeforeExtraction (grey image may be replaced, e.g. enhanced)
//   -> ORB extraction -> kAfterExtraction -> kBeforeInitialPose -> initial pose (motion model /
//   reference keyframe / relocalisation, non-excluded features only) -> kAfterInitialPose ->
//   local-map tracking -> kBeforeFinalPose -> final pose optimisation -> keyframe decision ->
//   kOnKeyFrameCreated + map modules' OnKeyFrame (only when a keyframe was made) -> local mapping
//   and local BA -> kOnMapUpdate + map modules' OnMapUpdate -> next frame.
//   After the last frame: every stage's and map module's Finish (outputs, errors -> run.json).
#pragma once

namespace dynref {

enum class Hook {
  kBeforeExtraction,
  kAfterExtraction,
  kBeforeInitialPose,
  kAfterInitialPose,
  kBeforeFinalPose,
  kOnKeyFrameCreated,
  kOnMapUpdate,
};

inline const char* HookName(Hook h) {
  switch (h) {
    case Hook::kBeforeExtraction: return "before_extraction";
    case Hook::kAfterExtraction: return "after_extraction";
    case Hook::kBeforeInitialPose: return "before_initial_pose";
    case Hook::kAfterInitialPose: return "after_initial_pose";
    case Hook::kBeforeFinalPose: return "before_final_pose";
    case Hook::kOnKeyFrameCreated: return "on_keyframe_created";
    case Hook::kOnMapUpdate: return "on_map_update";
  }
  return "?";
}

}  // namespace dynref
