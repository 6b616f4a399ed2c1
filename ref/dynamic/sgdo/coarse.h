// seed 001, Sec. 3.3 + Fig. 11: coarse rejection = combination of the dynamic mask M (S) and the
// per-point epipolar test (G). spec 001 E1: the paper never writes the combination down.
//   kPerPoint (spec's proposed reading, default): M only keeps pairs out of the F estimate;
//     a keypoint is rejected iff its epipolar distance D > th_epi (inside or outside M);
//     keypoints in M without a tracked pair are rejected, outside M without a pair kept.
//   kInstanceVote (DS-SLAM / SG-SLAM style alternative): inside M a dynamic instance is moving
//     iff (#paired points with D > th_epi) / (#paired points) >= vote_ratio (or it has no paired
//     point); all keypoints of a moving instance are rejected, of a still one kept. Outside M the
//     per-point epipolar test applies as in kPerPoint.
//   kMaskOnly = ablation (S): every keypoint in M rejected, no epipolar test.
//   kEpipolarOnly = ablation (G): no M at all; D > th_epi rejects, no pair keeps.
#pragma once
#include <string>
#include <vector>

namespace dynref::sgdo {

enum class CoarseMode { kPerPoint, kInstanceVote, kMaskOnly, kEpipolarOnly };
CoarseMode ParseCoarseMode(const std::string& text);  // "per_point" | "instance_vote" | "mask_only" | "epipolar_only"
const char* CoarseModeName(CoarseMode mode);

struct CoarseOptions {
  CoarseMode mode = CoarseMode::kPerPoint;
  double epipolar_threshold_px = 1.0;  // th_epi, not stated: DS-SLAM limit_dis_epi
  double vote_ratio = 0.5;             // kInstanceVote only; not stated (majority)
  void Check() const;
};

// Per keypoint input of the combination.
struct CoarseInput {
  int instance = 0;            // dynamic instance id covering the keypoint, 0 = outside M
  bool has_distance = false;   // tracked, unpruned pair and a valid F
  double epipolar_distance_px = 0;
  // Why there is no distance (issue 21): "no-pair" (LK failed), "pruned" (DS-SLAM border / patch
  // SAD: the flow is not trusted, so the point is not judged by it) or "no-F" (fewer than 8 usable
  // pairs in the frame: no epipolar test at all).
  std::string no_distance = "no-pair";
};

struct CoarseDecision {
  bool keep = true;
  std::string reason;  // "static", "epipolar", "mask", "instance-vote", "instance-still", and
                       // for points without a distance "<no_distance>" (kept) or
                       // "mask-<no_distance>" (in M, rejected)
};

struct CoarseResult {
  std::vector<CoarseDecision> decisions;  // per input
  // kInstanceVote: (instance id, votes dynamic, paired, moving), ascending id.
  struct Vote { int instance; int dynamic; int paired; bool moving; };
  std::vector<Vote> votes;
};

CoarseResult CombineCoarse(const std::vector<CoarseInput>& inputs, const CoarseOptions& options);

}  // namespace dynref::sgdo
