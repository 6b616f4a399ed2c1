// The backbone's per-frame work (hooks in method/hooks.h): load, before-extraction stages, ORB
// extraction, tracking with the method's stages between its steps, keyframe decision, map
// modules and sequential local mapping (busy or idle for the keyframe decision by the virtual
// mapping clock, ref/mapping/mapping_clock.h). One FrameLoop per run; it owns the map, the tracker and
// the local mapper, and counts what run.json reports.
#pragma once
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "features/keypoint_extractor.h"
#include "map/map.h"
#include "loop/loop_closer.h"
#include "mapping/local_mapper.h"
#include "mapping/mapping_clock.h"
#include "method/frame_edit.h"
#include "method/map_module.h"
#include "method/session.h"
#include "method/stage.h"
#include "structure/structure_tracker.h"
#include "pipeline/pipeline.h"
#include "pipeline/run_inputs.h"
#include "trace/trace_writer.h"
#include "tracking/place_index.h"
#include "tracking/tracker.h"

namespace dynref {

// Per-frame module times in ms of thread CPU time (run.json only, never in results).
struct ModuleTimings {
  std::vector<double> load, extraction, tracking, mapping, ba, slam, total;
  // Part of extraction when a config enables lines / planes (issue 13): segments + LBD, AHC.
  std::vector<double> lines, planes;
  // --variant concurrent: wall ms per keyframe in the local-mapping thread (local mapping, then
  // the on_map_update stages and map modules).
  std::vector<double> mapping_thread;
};

class FrameLoop {
 public:
  FrameLoop(const RunOptions& options, const RunInputs& inputs, Session& session, trace::TraceWriter& trace);
  ~FrameLoop();  // stops the local-mapping thread if Drain was not called
  // Processes inputs.frames[k]. Bad input mid-run (an unreadable frame, a detection mask of the
  // wrong size, a stage rejecting its input) ends the run cleanly: returns false with
  // result().end_state = "error: frame N (stamp): ..." and exit code 2.
  bool Process(size_t k);
  // --variant concurrent: local mapping works off its queue, then its thread stops; a mapping
  // error ends the run (result().end_state). Nothing to do for the oracle. Call before reading
  // map() etc. after the last frame.
  void Drain();
  // Keyframes, points and lost frames for the progress display (safe while mapping runs).
  std::string ProgressLine();

  const Map& map() const { return map_; }
  const tracking::Tracker& tracker() const { return tracker_; }
  const mapping::LocalMapper& mapper() const { return mapper_; }
  const loop::LoopCloser* loop_closer() const { return loop_.get(); }  // null: loop closing off
  RunResult& result() { return result_; }
  const std::vector<std::pair<int, std::string>>& lost_reasons() const { return lost_reasons_; }
  const ModuleTimings& timings() const { return timings_; }
  const Session& session() const { return session_; }
  int frames_zero_depth() const { return n_zero_depth_; }
  int frames_all_excluded() const { return n_all_excluded_; }

 private:
  using MapLock = std::unique_lock<std::mutex>;  // held in concurrent mode, else never locked
  // What tracking decided for one frame.
  struct TrackOutcome {
    bool ok = false;
    KeyFrame* new_kf = nullptr;  // made by initialisation or the keyframe decision
    std::string lost_reason;     // when !ok
  };
  // Module clock readings of one frame (ms) and the times measured inside a step.
  struct FrameTimes {
    double start = 0, loaded = 0, extracted = 0, tracked = 0, mapped = 0, finished = 0;
    double ba_ms = 0, lines_ms = 0, planes_ms = 0;
  };

  // Process's steps in order (frame_steps.cpp). In concurrent mode `lock` is held except while
  // a step decodes images or extracts ORB features.
  void StartMapperThread();
  void LoadFrame(const FrameEntry& e, Frame& f, FrameDetections& dets, MapLock& lock);
  StageContext StageContextFor(FrameEdit& edit);  // the tracking state before this frame
  void RunBeforeExtraction(Frame& f, StageContext& ctx);
  void ExtractFeatures(Frame& f, MapLock& lock, FrameTimes& times);
  void ExtractPoints(Frame& f);
  void RunAfterExtraction(Frame& f, StageContext& ctx);
  TrackOutcome Initialise(Frame& f);
  TrackOutcome Track(Frame& f, StageContext& ctx);
  KeyFrame* DecideKeyFrame(Frame& f);
  double HandOverKeyFrame(Frame& f, KeyFrame& kf, StageContext& ctx);  // returns local BA ms
  double MapKeyFrameNow(const Frame& f, KeyFrame& kf, StageContext& ctx, const MapModuleContext& mctx);
  void AfterLocalMapping(KeyFrame& kf, const MapModuleContext& mctx);
  void EndFrame(Frame& f, const TrackOutcome& t);
  void CountFrame(size_t k, const TrackOutcome& t);
  // Trace records and module timings of a frame (frame_trace.cpp).
  void TraceTrackedFrame(const Frame& f, bool ok);
  void TraceObservations(const Frame& f);
  void TraceStructure(const Frame& f, bool ok);
  void RecordTimings(const FrameTimes& t);
  // Local mapping of a new keyframe and the on_map_update stages / map modules: inline after the
  // frame (oracle) or in the mapping thread (concurrent).
  void MapperLoop();
  void MapQueuedKeyFrame(int64_t id);
  const RunOptions& options_;
  const RunInputs& inputs_;
  Session& session_;
  trace::TraceWriter& trace_;
  const Camera& camera_;
  std::unique_ptr<features::KeypointExtractor> extractor_;  // backbone features (orb | sift | onnx)
  ScalePyramid pyramid_;  // of the extractor's profile
  bool rgb_flag_;
  double depth_edge_rel_;  // backbone.depth_edge_rel (Frame::FinishFeatures)
  Map map_;
  tracking::Tracker tracker_;
  mapping::LocalMapper mapper_;
  std::unique_ptr<structure::StructureTracker> structure_;  // lines / planes (issue 13), else nullptr
  // Vocabulary + keyframe database (issue 34) when the backbone uses one, else nullptr. A keyframe
  // joins after its local mapping (ORB-SLAM2 adds it in LoopClosing), bad ones leave first.
  std::unique_ptr<tracking::PlaceIndex> place_;
  std::unique_ptr<loop::LoopCloser> loop_;  // backbone.loop_closing (issue 34), after local mapping
  mapping::MappingClock mapping_clock_;  // when local mapping counts as busy (issue 18)
  int clock_options_max_queue_;
  double (*now_)();  // module timing clock
  RunResult result_;
  std::vector<std::pair<int, std::string>> lost_reasons_;  // frame position -> reason
  ModuleTimings timings_;
  int n_zero_depth_ = 0, n_all_excluded_ = 0;
  // --variant concurrent (ORB-SLAM2's LocalMapping thread). One mutex guards the map, tracker,
  // session and trace: the tracker holds it for a frame except while it decodes the images and
  // extracts ORB features, the mapping thread while it maps one keyframe, so the two overlap and
  // which map state a frame sees depends on timing (the non-determinism the oracle removes).
  bool concurrent_ = false;
  std::mutex mutex_;
  std::condition_variable queue_cv_;
  std::deque<int64_t> queue_;  // keyframe ids waiting for local mapping
  bool mapper_busy_ = false, stop_ = false;
  std::string mapper_error_;
  std::thread mapper_thread_;
};

}  // namespace dynref
