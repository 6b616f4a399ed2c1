// Virtual clock of a concurrent local mapper, for a deterministic single-threaded run (issue 18).
//
// ORB-SLAM2 runs local mapping in its own thread. Tracking asks it "are you idle?"
// (LocalMapping::AcceptKeyFrames) before inserting a keyframe: while mapping is busy, a new
// keyframe needs the 30-frame timeout or a collapse of tracked points (Tracking::NeedNewKeyFrame
// c1a/c1c), and RGB-D inserts it only while fewer than 3 keyframes wait in the queue. Run
// sequentially, mapping is idle at every frame, so in dynamic scenes, where the inlier ratio
// stays low, nearly every frame became a keyframe (the "keyframe storm": 288 of 300 frames on
// walking_xyz, local BA over ~23 000 observations per keyframe).
//
// The clock charges each processed keyframe a VIRTUAL cost, from its problem size only
// (ms_per_keyframe + ms_per_ba_observation * local-BA observations: never the wall clock), and
// keeps mapping busy for that long in the sequence's own timestamps. The work itself still runs
// at once (zero latency: the next frame tracks against the updated map); only the keyframe
// decisions see the busy mapper. Deviations from ORB-SLAM2, documented in ref/mapping/README.md:
// no latency, and local BA is never interrupted or skipped when a newer keyframe waits.
#pragma once
#include <deque>
#include <limits>

#include "mapping/local_mapper.h"

namespace dynref::mapping {

struct MappingClockOptions {
  bool enabled = true;  // false: mapping idle at every frame (the plain sequential run)
  // Calibrated on the reference machine (2-core x86-64, Debian bookworm, Release): CPU time of
  // LocalMapper::ProcessKeyFrame over 275 keyframes of synthetic walking_xyz and static_xyz
  // (seed 1, 200 frames) fits 12 ms + 0.016 ms per local-BA observation.
  double ms_per_keyframe = 12.0;
  double ms_per_ba_observation = 0.016;
  int max_queue = 3;  // ORB-SLAM2 Tracking::NeedNewKeyFrame: KeyframesInQueue() < 3 (RGB-D)
  void Check() const;
};

// What tracking sees of local mapping at one frame.
struct MappingLoad {
  bool idle = true;  // ORB-SLAM2 LocalMapping::AcceptKeyFrames()
  int queued = 0;    // keyframes inserted whose (virtual) processing has not started
};

class MappingClock {
 public:
  explicit MappingClock(const MappingClockOptions& options);
  MappingLoad LoadAt(double stamp) const;
  // Charges a keyframe inserted at `stamp` whose mapping produced `stats`; returns its virtual
  // cost in ms. Mapping works on keyframes in insertion order, one at a time.
  double Charge(double stamp, const LocalMapperStats& stats);

 private:
  MappingClockOptions options_;
  std::deque<double> starts_;  // virtual start times of charged keyframes, ascending
  double free_at_ = -std::numeric_limits<double>::infinity();
};

}  // namespace dynref::mapping
