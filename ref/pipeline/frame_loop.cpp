// The frame loop; see frame_loop.h and method/hooks.h for the order of steps and hooks.
#include "pipeline/frame_loop.h"

#include <algorithm>
#include <stdexcept>

#include "core/cpu_clock.h"
#include "core/error.h"

namespace dynref {

FrameLoop::FrameLoop(const RunOptions& options, const RunInputs& inputs, Session& session, trace::TraceWriter& trace)
    : options_(options),
      inputs_(inputs),
      session_(session),
      trace_(trace),
      camera_(inputs.sequence.camera),
      extractor_(features::MakeExtractor(inputs.config->backbone.Extractor())),
      pyramid_(ScalePyramid::Make(extractor_->profile().n_levels, extractor_->profile().scale_factor)),
      rgb_flag_(inputs.config->backbone.camera_rgb_flag),
      depth_edge_rel_(inputs.config->backbone.depth_edge_rel),
      tracker_(camera_, map_, inputs.config->backbone.tracker, trace),
      mapper_(map_, camera_, inputs.config->backbone.mapper, trace),
      mapping_clock_(inputs.config->backbone.mapping_clock),
      clock_options_max_queue_(inputs.config->backbone.mapping_clock.max_queue),
      // Module timings: the thread's CPU clock (core/cpu_clock.h), wall clock with other threads.
      now_(options.threads > 1 || options.variant == "concurrent" ? WallMs : ThreadCpuMs),
      concurrent_(options.variant == "concurrent") {
  // With lines / planes, one of the threads extracts them beside ORB (Process).
  extractor_->set_threads(inputs.config->backbone.structure.enabled() ? std::max(1, options.threads - 1)
                                                                     : options.threads);
  map_.AddObserver(&session_);  // landmark events reach the method's components
  if (concurrent_) trace_.SetThreadSafe(true);  // local BA logs its residuals while tracking goes on
  if (inputs.config->backbone.structure.enabled()) {
    structure_ = std::make_unique<structure::StructureTracker>(camera_, inputs.config->backbone.structure, trace);
    tracker_.SetStructure(structure_.get());
    mapper_.SetStructure(structure_.get());
  }
  if (inputs.config->backbone.UsesVocabulary()) {
    place_ = std::make_unique<tracking::PlaceIndex>(inputs.config->backbone.vocabulary);
    tracker_.SetPlaceIndex(place_.get());
  }
  if (inputs.config->backbone.loop.enabled)
    loop_ = std::make_unique<loop::LoopCloser>(map_, camera_, inputs.config->backbone.loop, inputs.config->backbone.mapper.ba,
                                               trace);
  if (loop_ && structure_) loop_->SetStructure(structure_.get());
}

FrameLoop::~FrameLoop() {
  Drain();
  map_.RemoveObserver(&session_);
}

void FrameLoop::Drain() {
  if (!mapper_thread_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  queue_cv_.notify_one();
  mapper_thread_.join();
  if (!mapper_error_.empty() && result_.exit_code == 0) {
    result_.end_state = "error: local mapping: " + mapper_error_;
    result_.exit_code = kExitBadInput;
  }
}

std::string FrameLoop::ProgressLine() {
  std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
  if (concurrent_) lock.lock();
  return "keyframes " + std::to_string(map_.keyframes.size()) + "  points " + std::to_string(map_.GoodPointCount()) +
         "  lost " + std::to_string(lost_reasons_.size()) + (concurrent_ ? "  mapping queue " + std::to_string(queue_.size()) : "");
}

void FrameLoop::StartMapperThread() {
  if (concurrent_ && !mapper_thread_.joinable() && !stop_) mapper_thread_ = std::thread([this] { MapperLoop(); });
}

void FrameLoop::MapperLoop() {
  MapLock lock(mutex_);
  mapper_.SetMapLock(&lock);  // local BA solves unlocked
  for (;;) {
    queue_cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopped with nothing left to map
    const int64_t id = queue_.front();
    queue_.pop_front();
    mapper_busy_ = true;
    const double t0 = WallMs();
    try {
      MapQueuedKeyFrame(id);
    } catch (const std::exception& e) {
      mapper_error_ = "keyframe " + std::to_string(id) + ": " + e.what();
      queue_.clear();
      stop_ = true;
    }
    timings_.mapping_thread.push_back(WallMs() - t0);
    mapper_busy_ = false;
    // Let the tracker in between two keyframes.
    lock.unlock();
    std::this_thread::yield();
    lock.lock();
  }
}

// In the mapping thread: local mapping, then the on_map_update stages (with a context of the
// keyframe alone) and the map modules.
void FrameLoop::MapQueuedKeyFrame(int64_t id) {
  KeyFrame* kf = map_.kf(id);
  if (kf == nullptr || kf->bad) return;
  mapper_.ProcessKeyFrame(id);
  FrameEdit kf_edit(kf->frame, map_, Hook::kOnMapUpdate);
  StageContext ctx{kf_edit, nullptr, tracker_.reference_kf(), map_, camera_, trace_, true, false};
  ctx.new_keyframe = kf;
  ctx.new_keyframe_edit = &kf_edit;
  ctx.threads = options_.threads;
  session_.Run(Hook::kOnMapUpdate, ctx);
  AfterLocalMapping(*kf, MapModuleContext{kf->frame, *kf, map_, camera_, trace_, options_.threads});
}

// ORB-SLAM2's per-frame order (method/hooks.h): load, before_extraction stages, features,
// after_extraction / before_initial_pose stages, tracking (with its stages between the steps)
// and the keyframe decision, the new keyframe's stages and local mapping, the frame's end.
bool FrameLoop::Process(size_t k) {
  StartMapperThread();
  MapLock lock(mutex_, std::defer_lock);
  if (concurrent_) lock.lock();
  const FrameEntry& e = inputs_.frames[k];
  trace_.BeginFrame(e.index, e.rgb_stamp);
  FrameTimes times;
  times.start = now_();
  Frame f;
  FrameDetections dets;
  try {
    LoadFrame(e, f, dets, lock);
    times.loaded = now_();
    FrameEdit edit(f, map_, Hook::kBeforeExtraction);
    StageContext ctx = StageContextFor(edit);
    RunBeforeExtraction(f, ctx);
    ExtractFeatures(f, lock, times);
    times.extracted = now_();
    RunAfterExtraction(f, ctx);
    const TrackOutcome t = ctx.initialised ? Track(f, ctx) : Initialise(f);
    times.tracked = now_();
    TraceTrackedFrame(f, t.ok);
    if (t.new_kf != nullptr) times.ba_ms = HandOverKeyFrame(f, *t.new_kf, ctx);
    times.mapped = now_();
    EndFrame(f, t);
    times.finished = now_();
    RecordTimings(times);
    CountFrame(k, t);
    return true;
  } catch (const std::exception& err) {
    result_.end_state = "error: frame " + std::to_string(e.index) + " (" + e.rgb_stamp_text + "): " + err.what();
    result_.exit_code = kExitBadInput;
    return false;
  }
}

}  // namespace dynref
