// ORB-SLAM2 LoopClosing::DetectLoop (Mur-Artal & Tardos, T-RO 2017, Sec. V "Loop closing" step A,
// loop candidates detection; Mur-Artal et al., T-RO 2015, Sec. VII-A), on dynref's map and place
// index, deterministic (every set ordered by keyframe id):
//  1. skipped while fewer than `min_keyframes_since_loop` (10) keyframes were created since the
//     last loop (ORB-SLAM2: mnId < mLastLoopKFid + 10; the last loop starts at keyframe 0);
//  2. min_score = the lowest BoW score between the keyframe and its (good) covisible keyframes,
//     those of weight >= 15 (kf.ordered_covisibles, ORB-SLAM2 GetVectorCovisibleKeyFrames; a
//     weakly connected keyframe would lower the bar);
//  3. candidates = KeyFrameDatabase::DetectLoopCandidates(kf, min_score) (place/keyframe_database.h);
//  4. covisibility consistency: each candidate's group (itself + its connected keyframes) is
//     consistent with a group of the previous detection when they share a keyframe; its
//     consistency is then that group's + 1, and the candidate is accepted ("enough consistent")
//     once that reaches `consistency` (3). Each previous group carries over at most once (the
//     first consistent candidate, in candidate order); a candidate consistent with no group starts
//     a new one at 0. The groups of this detection replace the previous ones (cleared when there
//     is no candidate). ORB-SLAM2 leaves the groups untouched on a skipped keyframe; so does this.
#pragma once
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "map/map.h"
#include "place/keyframe_database.h"
#include "tracking/place_index.h"

namespace dynref::loop {

struct LoopDetectorOptions {
  int min_keyframes_since_loop = 10;  // ORB-SLAM2 LoopClosing::DetectLoop: mLastLoopKFid + 10
  int consistency = 3;                // ORB-SLAM2 mnCovisibilityConsistencyTh
  void Check() const;                 // InputError naming the field
};

// One database candidate and what consistency made of it.
struct LoopCandidate {
  int64_t kf = -1;
  float score = 0;       // BoW score with the query keyframe (the database's)
  int consistency = 0;   // highest consistency over the previous groups it continues (0: none)
  bool accepted = false; // consistency >= options.consistency
  std::string reason;    // "consistent", "not-consistent-enough", "new-group"
};

struct LoopDetection {
  bool skipped = false;       // step 1
  float min_score = 1;        // step 2
  place::PlaceQueryReport query;
  std::vector<LoopCandidate> candidates;  // in the database's order
  std::vector<int64_t> accepted;          // mvpEnoughConsistentCandidates
};

class LoopDetector {
 public:
  explicit LoopDetector(const LoopDetectorOptions& options);
  // DetectLoop for keyframe `kf` of `map` (its vectors must be in `place`).
  LoopDetection Detect(const KeyFrame& kf, const Map& map, const tracking::PlaceIndex& place);
  // A loop was closed at keyframe `kf_id` (mLastLoopKFid).
  void SetLastLoop(int64_t kf_id) { last_loop_kf_ = kf_id; }
  // The consistency groups carried to the next detection: (group, consistency), in creation order.
  const std::vector<std::pair<std::set<int64_t>, int>>& groups() const { return groups_; }

 private:
  LoopDetectorOptions options_;
  int64_t last_loop_kf_ = 0;
  std::vector<std::pair<std::set<int64_t>, int>> groups_;
};

}  // namespace dynref::loop
