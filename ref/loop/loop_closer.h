// ORB-SLAM2's LoopClosing thread run sequentially after the local mapping of each keyframe
// (Mur-Artal & Tardos, "ORB-SLAM2", T-RO 2017, Sec. V; Mur-Artal, Montiel & Tardos, "ORB-SLAM",
// T-RO 2015, Sec. VII), deterministic (one thread, seeded RANSAC, id-ordered containers):
//  1. DetectLoop (loop_detector.h);
//  2. ComputeSim3 with fixed scale: for each accepted candidate in order, SearchByBoW between the
//     keyframes (ratio 0.75, >= 20 matches), SE(3) RANSAC (se3_solver.h, >= 20 inliers); the first
//     candidate that passes gives T_cw of the keyframe seen from the loop keyframe. Then the loop
//     keyframe's and its covisibles' map points are projected into the keyframe (th 10) and the
//     loop is accepted with >= 40 matched points;
//  3. CorrectLoop: the keyframe's covisibles get the correction propagated through their relative
//     poses, their map points are moved with them, the loop matches are fused (the keyframe's
//     point is replaced by the loop point) and the loop points are fused into every corrected
//     keyframe (th 4); the new loop connections feed
//  4. the essential-graph optimisation (essential_graph.h): spanning tree, loop edges, covisibility
//     edges of weight >= 100, the new loop connections; the loop keyframe fixed; map points follow
//     their reference keyframe;
//  5. global bundle adjustment (ORB-SLAM2 RunGlobalBundleAdjustment, Optimizer::BundleAdjustment:
//     every keyframe and point, keyframe 0 fixed, 10 iterations) through optim::LocalBundleAdjust
//     with every keyframe free, Huber throughout and no refinement phase; a method's
//     per-observation weights and exclusions apply as in local BA, and the backbone's line and
//     plane landmarks join it as in local BA (global_ba.h). No observation is erased (ORB-SLAM2's
//     global BA flags no outlier). After the essential graph, lines and planes follow the keyframe
//     that created them (global_ba.h MoveStructureWithKeyFrames).
// Deliberate deviations: ORB-SLAM2 interleaves 5 RANSAC iterations per candidate and refines the
// transform with OptimizeSim3 after a SearchBySim3; here each candidate gets a full RANSAC and the
// closed-form refit of its inliers. ORB-SLAM2's global BA runs in a thread and is merged later; here
// it runs at once. ORB-SLAM2's RunGlobalBundleAdjustment passes bRobust = false (no Huber kernel);
// here Huber stays on (the methods keep down-weighted observations of movers in the map; the
// non-robust variant is not measured).
// Trace: see loop_trace.h.
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/rng.h"
#include "io/camera.h"
#include "loop/loop_detector.h"
#include "loop/se3_solver.h"
#include "map/map.h"
#include "optim/optim.h"
#include "structure/structure_tracker.h"
#include "trace/trace_writer.h"
#include "tracking/place_index.h"

namespace dynref::loop {

struct LoopClosingOptions {
  bool enabled = true;               // ORB-SLAM2 runs LoopClosing (backbone.loop_closing)
  LoopDetectorOptions detector;
  int bow_min_matches = 20;          // ORB-SLAM2 ComputeSim3: nmatches < 20 discarded
  Se3RansacOptions ransac;           // ORB-SLAM2 SetRansacParameters(0.99, 20, 300)
  int min_loop_matches = 40;         // ORB-SLAM2 ComputeSim3: nTotalMatches >= 40
  int essential_min_weight = 100;    // ORB-SLAM2 OptimizeEssentialGraph minFeat
  int essential_iterations = 20;     // optimize(20)
  bool global_ba = true;
  int global_ba_iterations = 10;     // RunGlobalBundleAdjustment(..., 10)
  uint64_t seed = 1;
  void Check() const;  // InputError naming the field
};

// One closed loop (for run outputs and tests).
struct LoopEvent {
  int64_t kf = -1, loop_kf = -1;
  int bow_matches = 0, se3_inliers = 0, loop_matches = 0;
  SE3 T_cw_before = SE3::Identity(), T_cw_after = SE3::Identity();  // the keyframe's
  double essential_chi2_start = 0, essential_chi2_end = 0;
};

// CPU time (thread clock of the thread that ran it) of loop closing, for run.json (issue 34 cost).
struct LoopTiming {
  int64_t keyframes = 0, loops = 0;  // keyframes processed, loops closed
  double detect_ms = 0;              // DetectLoop + ComputeSe3, every keyframe
  double correct_ms = 0;             // CorrectLoop without the global BA (fusion, essential graph)
  double global_ba_ms = 0;
};

class LoopCloser {
 public:
  LoopCloser(Map& map, const Camera& camera, const LoopClosingOptions& options, const optim::LocalBAOptions& ba,
             trace::TraceWriter& trace);
  // After the local mapping of keyframe `kf_id` (already in `place`). Returns true when a loop
  // was closed (the map changed).
  bool Process(int64_t kf_id, tracking::PlaceIndex& place);
  // The backbone's line and plane landmarks (null: points only): they follow their keyframes
  // after the correction and join the global BA (global_ba.h).
  void SetStructure(const structure::StructureTracker* s) { structure_ = s; }
  const std::vector<LoopEvent>& loops() const { return loops_; }
  const LoopTiming& timing() const { return timing_; }

 private:
  struct Candidate {
    int64_t loop_kf = -1;
    SE3 T_cw = SE3::Identity();          // the keyframe's pose through the loop
    std::vector<int64_t> matched;        // per keyframe feature: loop map point or -1
    std::vector<int64_t> loop_points;    // the loop keyframe's and its covisibles' points
    int bow_matches = 0, se3_inliers = 0, loop_matches = 0;
  };
  // DetectLoop and ComputeSe3 (steps 1-2): true with the loop in `out`.
  bool DetectAndMatch(KeyFrame& kf, tracking::PlaceIndex& place, Candidate* out);
  bool ComputeSe3(const KeyFrame& kf, const std::vector<int64_t>& accepted, const tracking::PlaceIndex& place,
                  Candidate* out);
  void CorrectLoop(KeyFrame& kf, const Candidate& c, LoopEvent* event);
  void GlobalBundleAdjustment();

  Map& map_;
  const Camera& camera_;
  LoopClosingOptions options_;
  optim::LocalBAOptions ba_;
  trace::TraceWriter& trace_;
  LoopDetector detector_;
  Rng rng_;
  std::map<int64_t, std::set<int64_t>> loop_edges_;  // ORB-SLAM2 KeyFrame::mspLoopEdges
  std::vector<LoopEvent> loops_;
  int essential_calls_ = 0, global_ba_calls_ = 0;
  LoopTiming timing_;
  const structure::StructureTracker* structure_ = nullptr;
};

}  // namespace dynref::loop
