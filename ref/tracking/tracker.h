// ORB-SLAM2 Tracking (RGB-D, SLAM mode) as explicit steps the pipeline calls in frame order, so
// that method stages run between them (ref/method/hooks.h). Single-threaded: local mapping
// runs after each keyframe (ref/mapping); whether it counts as idle for the keyframe decision
// comes from the virtual mapping clock (ref/mapping/mapping_clock.h).
#pragma once
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "features/mnn2.h"
#include "map/frame.h"
#include "map/map.h"
#include "structure/structure_tracker.h"
#include "optim/optim.h"
#include "trace/trace_writer.h"

namespace dynref::tracking {

class PlaceIndex;      // place_index.h
struct PlaceBow;        // place_index.h
struct ProjectedPoint;  // matcher.h

struct TrackerOptions {
  int min_init_points = 500;   // ORB-SLAM2 StereoInitialization: N > 500 (here: with depth)
  int max_frames = 30;         // ORB-SLAM2 mMaxFrames = fps
  int min_frames = 0;          // ORB-SLAM2 mMinFrames
  int reloc_recent_keyframes = 10;  // relocalisation candidates (no BoW database: most recent)
  // Issue 34 (tracking/relocaliser_bow.h): "bow" = ORB-SLAM2's keyframe-database query over the
  // whole map; "recent" = the reloc_recent_keyframes most recent keyframes (dynref before it).
  std::string relocalisation = "bow";
  bool bow_matching = false;  // ORB-SLAM2 SearchByBoW in reference-keyframe tracking / relocalisation
  int ransac_iterations = 300; // ORB-SLAM2 PnPsolver SetRansacParameters(0.99, 10, 300, 4, 0.5, 5.991)
  uint64_t seed = 1;
  optim::PoseOnlyOptions pose;  // ORB-SLAM2 Optimizer::PoseOptimization (4 x 10 iterations, chi2 gates)
  features::BackboneMnn2 mnn2;  // seed 004 MNN2 in keyframe-to-frame matching (off: ORB-SLAM2)
  void Check() const;
};

enum class TrackState { kNotInitialised, kOk, kLost };
const char* TrackStateName(TrackState s);

// Per-frame record for the trajectory (ORB-SLAM2 mlRelativeFramePoses / mlbLost).
struct FrameRecord {
  int index = 0;
  double stamp = 0;
  std::string stamp_text;
  int64_t ref_kf = -1;
  SE3 T_cr = SE3::Identity();  // camera from reference keyframe
  bool lost = true;
};

class Tracker {
 public:
  Tracker(const Camera& camera, Map& map, const TrackerOptions& options, trace::TraceWriter& trace);

  TrackState state() const { return state_; }
  const Frame* last_frame() const { return has_last_ ? &last_ : nullptr; }
  KeyFrame* reference_kf() { return map_.kf(reference_kf_); }
  const std::vector<FrameRecord>& records() const { return records_; }

  // Map initialisation from f when it has enough non-excluded features with depth: pose
  // identity, a keyframe and one map point per such feature. Returns the keyframe or nullptr.
  KeyFrame* TryInitialise(Frame& f);
  // Initial pose: motion model (else reference keyframe), or relocalisation when lost; each with
  // pose optimisation ("track.pose#1"...). Returns success.
  bool TrackInitial(Frame& f);
  // Local map search (ORB-SLAM2 UpdateLocalMap + SearchLocalPoints), no optimisation.
  void SearchLocalMap(Frame& f);
  // Final pose optimisation and ORB-SLAM2's TrackLocalMap success test; on success updates the
  // motion model (before local mapping, as ORB-SLAM2 Tracking::Track).
  bool OptimizeFinal(Frame& f);
  // mapping_idle: ORB-SLAM2 LocalMapping::AcceptKeyFrames(); keyframes_queued: its queue
  // length (ref/mapping/mapping_clock.h models both deterministically).
  bool NeedNewKeyFrame(const Frame& f, bool mapping_idle = true, int keyframes_queued = 0,
                       int max_queue = 3) const;
  KeyFrame* CreateNewKeyFrame(Frame& f);
  // Ends the frame: outlier cleanup, last frame, trajectory record.
  void FinishFrame(Frame& f, bool ok);
  int matches_inliers() const { return matches_inliers_; }
  // Lines and planes (issue 13; nullptr = point-only ORB-SLAM2). Not owned.
  void SetStructure(const structure::StructureTracker* s) { structure_ = s; }
  // Place recognition (issue 34; nullptr = no vocabulary). Not owned.
  void SetPlaceIndex(PlaceIndex* p) { place_ = p; }
  int pose_calls() const { return pose_call_; }

 private:
  // tracker.cpp
  void TraceKeyFrame(const KeyFrame& k);          // PROB "track.keyframe" kf<id>: input frame
  void UpdateLastFramePose();
  void CheckReplacedInLastFrame();
  // pose_tracking.cpp
  bool TrackWithMotionModel(Frame& f);
  bool TrackReferenceKeyFrame(Frame& f);
  std::vector<optim::PoseObservation> PoseObservations(Frame& f, std::vector<int>* idx);
  int OptimizePose(Frame& f);                     // returns inliers (map points with obs)
  int DiscardOutliers(Frame& f);                  // returns matches with map observations
  // relocalise.cpp
  bool Relocalise(Frame& f);
  bool RelocaliseFrom(Frame& f, const KeyFrame& kf, const PlaceBow& frame_bow);
  bool RelocaliseSteps(Frame& f, const KeyFrame& kf, const PlaceBow& frame_bow, int* n_matches, int* n_pnp, int* n_good);
  int RelocaliseByProjection(Frame& f, const KeyFrame& kf, int good);  // returns the inliers
  bool PnpRansac(const Frame& f, const std::vector<int>& idx, const std::vector<Eigen::Vector3d>& X,
                 SE3* T_cw, std::vector<uint8_t>* inliers);
  // local_map.cpp
  std::map<int64_t, int> CountObservingKeyFrames(Frame& f);
  void UpdateLocalKeyFrames(Frame& f);
  void AddNeighbourKeyFrames(int frame_index);
  std::vector<int64_t> LocalPoints(int frame_index);
  std::vector<ProjectedPoint> LocalPointsInView(Frame& f, const std::vector<int64_t>& local_points);
  // new_keyframes.cpp
  KeyFrame* AddKeyFrameOf(const Frame& f);        // into the map, traced
  void AddPointFromDepth(Frame& f, const KeyFrame& k, int i);
  int AddPointsByDepth(Frame& f, KeyFrame& k);

  const Camera& camera_;
  Map& map_;
  TrackerOptions options_;
  trace::TraceWriter& trace_;
  Rng rng_;
  TrackState state_ = TrackState::kNotInitialised;
  Frame last_;
  bool has_last_ = false;
  SE3 velocity_ = SE3::Identity();
  bool has_velocity_ = false;
  int64_t reference_kf_ = -1;
  int last_kf_frame_ = -1;
  int last_reloc_frame_ = -1000000;
  int matches_inliers_ = 0;
  // Structure: weighted inlier lines/planes of the last OptimizeFinal (added to the point counts
  // in ORB-SLAM2's tracking thresholds, structure_options.h).
  const structure::StructureTracker* structure_ = nullptr;
  PlaceIndex* place_ = nullptr;  // issue 34, place_index.h
  int structure_inliers_ = 0;
  int StructureCount(double weighted) const { return static_cast<int>(std::floor(weighted)); }
  int pose_call_ = 0;
  int current_frame_ = -1;
  std::vector<int64_t> local_kfs_;
  std::vector<FrameRecord> records_;
};

}  // namespace dynref::tracking
