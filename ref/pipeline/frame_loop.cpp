// The frame loop; see frame_loop.h and method/hooks.h for the order of steps and hooks.
#include "pipeline/frame_loop.h"

#include <algorithm>

#include "core/cpu_clock.h"
#include "core/parallel.h"

#include <time.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/error.h"
#include "core/format.h"
#include "method/frame_edit.h"

namespace dynref {
namespace {


}  // namespace

FrameLoop::FrameLoop(const RunOptions& options, const RunInputs& inputs, Session& session, trace::TraceWriter& trace)
    : options_(options),
      inputs_(inputs),
      session_(session),
      trace_(trace),
      camera_(inputs.sequence.camera),
      extractor_(features::MakeExtractor(inputs.config->backbone.Extractor())),
      pyramid_(ScalePyramid::Make(extractor_->profile().n_levels, extractor_->profile().scale_factor)),
      rgb_flag_(inputs.config->backbone.camera_rgb_flag),
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

void FrameLoop::MapperLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  mapper_.SetMapLock(&lock);  // local BA solves unlocked
  for (;;) {
    queue_cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopped with nothing left to map
    const int64_t id = queue_.front();
    queue_.pop_front();
    mapper_busy_ = true;
    const double t0 = WallMs();
    try {
      KeyFrame* kf = map_.kf(id);
      if (kf != nullptr && !kf->bad) {
        mapper_.ProcessKeyFrame(id);
        FrameEdit kf_edit(kf->frame, map_, Hook::kOnMapUpdate);
        StageContext ctx{kf_edit, nullptr, tracker_.reference_kf(), map_, camera_, trace_, true, false};
        ctx.new_keyframe = kf;
        ctx.new_keyframe_edit = &kf_edit;
        ctx.threads = options_.threads;
        session_.Run(Hook::kOnMapUpdate, ctx);
        session_.OnMapUpdate(MapModuleContext{kf->frame, *kf, map_, camera_, trace_, options_.threads});
        if (place_ != nullptr) place_->AddAfterMapping(*kf, map_);
        if (loop_ != nullptr) loop_->Process(kf->id, *place_);
      }
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

bool FrameLoop::Process(size_t k) {
  if (concurrent_ && !mapper_thread_.joinable() && !stop_) mapper_thread_ = std::thread([this] { MapperLoop(); });
  std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
  if (concurrent_) lock.lock();
  const FrameEntry& e = inputs_.frames[k];
  trace_.BeginFrame(e.index, e.rgb_stamp);
  const double t0 = now_();
  Frame f;
  f.index = e.index;
  f.stamp = e.rgb_stamp;
  f.stamp_text = e.rgb_stamp_text;
  f.trace = &trace_;
  FrameDetections dets;
  try {
    if (!mapper_error_.empty()) throw std::runtime_error("local mapping failed: " + mapper_error_);
    if (concurrent_) lock.unlock();  // decoding reads no shared state
    inputs_.LoadFrame(e, options_, f, dets);
    if (concurrent_) lock.lock();
    const double t_loaded = now_();
    // f.rgb is BGR (cv::imread). ORB-SLAM2's rgbd_tum with Camera.RGB: 1 (TUM1-3.yaml) converts
    // those BGR images with CV_RGB2GRAY, so blue gets red's weight; backbone.camera_rgb_flag
    // reproduces that grey image (default), false gives the true luminance.
    cv::cvtColor(f.rgb, f.grey, rgb_flag_ ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
    if (cv::countNonZero(f.depth_m > 0) == 0) ++n_zero_depth_;
    const Frame* prev = tracker_.last_frame();
    const bool was_lost = tracker_.state() == tracking::TrackState::kLost;
    const bool initialised = tracker_.state() != tracking::TrackState::kNotInitialised;
    FrameEdit edit(f, map_, Hook::kBeforeExtraction);
    StageContext ctx{edit, prev, tracker_.reference_kf(), map_, camera_, trace_, initialised, was_lost};
    ctx.threads = options_.threads;
    const cv::Size grey_size = f.grey.size();
    session_.Run(Hook::kBeforeExtraction, ctx);
    if (f.grey.type() != CV_8U || f.grey.size() != grey_size)
      throw std::logic_error("a before_extraction stage changed the grey image's size or type");
    // Task 0: ORB keypoints and the per-key geometry; task 1: lines and planes. They read the
    // same images and write disjoint parts of the frame, and only task 1 writes trace records,
    // so with --threads > 1 they run side by side with the same bytes as one after the other.
    double lines_ms = 0, planes_ms = 0;
    // ORB extraction reads and writes only the frame: concurrent mapping goes on meanwhile (with
    // lines / planes, whose extraction writes trace records, the lock stays held).
    const bool release = concurrent_ && structure_ == nullptr;
    if (release) lock.unlock();
    ParallelFor(structure_ != nullptr ? 2 : 1, options_.threads, [&](int task) {
      if (task == 0) {
        extractor_->Extract(f.grey, &f.keys, &f.descriptors);
        f.match_profile = extractor_->profile();
        f.pyramid = pyramid_;
        f.FinishFeatures(camera_, inputs_.config->backbone.depth_edge_rel);
      } else {
        structure_->Extract(f, &lines_ms, &planes_ms);
      }
    });
    if (release) lock.lock();
    const double t1 = now_();
    trace_.FrameCount("extract", "keypoints", static_cast<int64_t>(f.N()));
    session_.Run(Hook::kAfterExtraction, ctx);
    session_.Run(Hook::kBeforeInitialPose, ctx);
    if (f.ExcludedCount() == static_cast<int>(f.N()) && f.N() > 0) ++n_all_excluded_;

    bool ok = false;
    KeyFrame* new_kf = nullptr;
    double ba_ms = 0;
    std::string lost_reason;
    if (!initialised) {
      new_kf = tracker_.TryInitialise(f);
      ok = new_kf != nullptr;
      if (!ok) lost_reason = "not-initialised";
      if (ok) trace_.FramePose("initial", f.T_cw.inverse());
    } else {
      ok = tracker_.TrackInitial(f);
      if (ok) {
        trace_.FramePose("initial", f.T_cw.inverse());
        ctx.reference_kf = tracker_.reference_kf();
        session_.Run(Hook::kAfterInitialPose, ctx);
        tracker_.SearchLocalMap(f);
        ctx.reference_kf = tracker_.reference_kf();
        session_.Run(Hook::kBeforeFinalPose, ctx);
        ok = tracker_.OptimizeFinal(f);
        if (!ok) lost_reason = "lost: local map tracking failed";
      } else {
        lost_reason = was_lost ? "lost: relocalisation failed" : "lost: initial pose failed";
      }
      if (ok) {
        // Oracle: the virtual mapping clock says whether local mapping is busy; concurrent: the
        // mapping thread itself (ORB-SLAM2's AcceptKeyFrames / KeyframesInQueue).
        const mapping::MappingLoad load =
            concurrent_ ? mapping::MappingLoad{!mapper_busy_ && queue_.empty(), static_cast<int>(queue_.size())}
                        : mapping_clock_.LoadAt(f.stamp);
        trace_.FrameCount("mapping", "idle", load.idle ? 1 : 0);
        trace_.FrameCount("mapping", "queued", load.queued);
        if (tracker_.NeedNewKeyFrame(f, load.idle, load.queued, clock_options_max_queue_))
          new_kf = tracker_.CreateNewKeyFrame(f);
      }
    }
    const double t2 = now_();
    if (ok) trace_.FramePose("final", f.T_cw.inverse());
    if (trace_.full_enabled()) {
      for (size_t i = 0; i < f.N(); ++i) {
        const cv::KeyPoint& kp = f.keys_un[i];
        // map_point_id: the final inlier association; associated: the point the stages saw,
        // kept through an exclusion or an outlier flag (trace schema 3, ref/trace/README.md).
        const int64_t mp = f.outlier[i] ? -1 : f.map_point_ids[i];
        const int64_t associated = f.AssociatedMapPoint(static_cast<int>(i));
        trace_.Observation(static_cast<int64_t>(i), mp, associated, kp.pt.x, kp.pt.y, f.depth[i] > 0 ? f.depth[i] : 0.0,
                           kp.octave, Fnv1a64(f.descriptors.ptr<uint8_t>(static_cast<int>(i)), f.descriptors.cols * f.descriptors.elemSize()));
      }
    }
    if (structure_ != nullptr) {
      structure_->TraceFrame(f);
      int lines = 0, planes = 0;
      for (size_t i = 0; i < f.structure.map_line_ids.size(); ++i) lines += f.structure.map_line_ids[i] >= 0;
      for (size_t j = 0; j < f.structure.map_plane_ids.size(); ++j) planes += f.structure.map_plane_ids[j] >= 0;
      trace_.FrameCount("structure.final", "line_residuals", ok ? lines : 0);
      trace_.FrameCount("structure.final", "plane_residuals", ok ? planes : 0);
    }
    if (new_kf != nullptr) {
      FrameEdit kf_edit(new_kf->frame, map_, Hook::kOnKeyFrameCreated);
      ctx.new_keyframe = new_kf;
      ctx.new_keyframe_edit = &kf_edit;
      ctx.reference_kf = tracker_.reference_kf();
      session_.Run(Hook::kOnKeyFrameCreated, ctx);
      const MapModuleContext mctx{f, *new_kf, map_, camera_, trace_, options_.threads};
      session_.OnKeyFrame(mctx);
      if (concurrent_) {
        queue_.push_back(new_kf->id);
        queue_cv_.notify_one();
      } else {
        const mapping::LocalMapperStats ms = mapper_.ProcessKeyFrame(new_kf->id);
        ba_ms = ms.ba_ms;
        const double cost_ms = mapping_clock_.Charge(f.stamp, ms);
        trace_.FrameCount("mapping", "virtual_cost_us", static_cast<int64_t>(std::llround(cost_ms * 1e3)));
        session_.Run(Hook::kOnMapUpdate, ctx);
        session_.OnMapUpdate(mctx);
        if (place_ != nullptr) place_->AddAfterMapping(*new_kf, map_);
        if (loop_ != nullptr) loop_->Process(new_kf->id, *place_);
      }
      ctx.new_keyframe_edit = nullptr;
    }
    const double t3 = now_();
    trace_.FrameCount("features", "excluded", f.ExcludedCount());
    trace_.FrameCount("track", "ok", ok ? 1 : 0);
    trace_.FrameCount("track", "keyframe", new_kf != nullptr ? 1 : 0);
    tracker_.FinishFrame(f, ok);
    const double t4 = now_();
    timings_.load.push_back(t_loaded - t0);
    timings_.extraction.push_back(t1 - t_loaded);
    timings_.tracking.push_back((t2 - t1) + (t4 - t3));
    timings_.mapping.push_back((t3 - t2) - ba_ms);
    timings_.ba.push_back(ba_ms);
    timings_.slam.push_back(t4 - t_loaded);
    timings_.total.push_back(t4 - t0);
    if (structure_ != nullptr) timings_.lines.push_back(lines_ms), timings_.planes.push_back(planes_ms);
    ++result_.frames;
    if (ok) ++result_.tracked;
    else lost_reasons_.emplace_back(static_cast<int>(k), lost_reason);
    return true;
  } catch (const std::exception& err) {
    result_.end_state = "error: frame " + std::to_string(e.index) + " (" + e.rgb_stamp_text + "): " + err.what();
    result_.exit_code = kExitBadInput;
    return false;
  }
}

}  // namespace dynref
