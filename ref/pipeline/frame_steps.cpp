// The steps of FrameLoop::Process in their order (frame_loop.h, method/hooks.h): load, stages
// before extraction, feature extraction, tracking with the method's stages between its steps, the
// keyframe decision, the new keyframe's stages and local mapping, the frame's end.
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/parallel.h"
#include "pipeline/frame_loop.h"

namespace dynref {

void FrameLoop::LoadFrame(const FrameEntry& e, Frame& f, FrameDetections& dets, MapLock& lock) {
  f.index = e.index;
  f.stamp = e.rgb_stamp;
  f.stamp_text = e.rgb_stamp_text;
  f.trace = &trace_;
  if (!mapper_error_.empty()) throw std::runtime_error("local mapping failed: " + mapper_error_);
  if (concurrent_) lock.unlock();  // decoding reads no shared state
  inputs_.LoadFrame(e, options_, f, dets);
  if (concurrent_) lock.lock();
  // f.rgb is BGR (cv::imread). ORB-SLAM2's rgbd_tum with Camera.RGB: 1 (TUM1-3.yaml) converts
  // those BGR images with CV_RGB2GRAY, so blue gets red's weight; backbone.camera_rgb_flag
  // reproduces that grey image (default), false gives the true luminance.
  cv::cvtColor(f.rgb, f.grey, rgb_flag_ ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  if (cv::countNonZero(f.depth_m > 0) == 0) ++n_zero_depth_;
}

StageContext FrameLoop::StageContextFor(FrameEdit& edit) {
  const bool was_lost = tracker_.state() == tracking::TrackState::kLost;
  const bool initialised = tracker_.state() != tracking::TrackState::kNotInitialised;
  StageContext ctx{edit, tracker_.last_frame(), tracker_.reference_kf(), map_, camera_, trace_, initialised, was_lost};
  ctx.threads = options_.threads;
  return ctx;
}

void FrameLoop::RunBeforeExtraction(Frame& f, StageContext& ctx) {
  const cv::Size grey_size = f.grey.size();
  session_.Run(Hook::kBeforeExtraction, ctx);
  if (f.grey.type() != CV_8U || f.grey.size() != grey_size)
    throw std::logic_error("a before_extraction stage changed the grey image's size or type");
}

// Task 0: ORB keypoints and the per-key geometry; task 1: lines and planes. They read the same
// images and write disjoint parts of the frame, and only task 1 writes trace records, so with
// --threads > 1 they run side by side with the same bytes as one after the other.
void FrameLoop::ExtractFeatures(Frame& f, MapLock& lock, FrameTimes& times) {
  // ORB extraction reads and writes only the frame: concurrent mapping goes on meanwhile (with
  // lines / planes, whose extraction writes trace records, the lock stays held).
  const bool release = concurrent_ && structure_ == nullptr;
  if (release) lock.unlock();
  ParallelFor(structure_ != nullptr ? 2 : 1, options_.threads, [&](int task) {
    if (task == 0) ExtractPoints(f);
    else structure_->Extract(f, &times.lines_ms, &times.planes_ms);
  });
  if (release) lock.lock();
}

void FrameLoop::ExtractPoints(Frame& f) {
  extractor_->Extract(f.grey, &f.keys, &f.descriptors);
  f.match_profile = extractor_->profile();
  f.pyramid = pyramid_;
  f.FinishFeatures(camera_, depth_edge_rel_);
}

void FrameLoop::RunAfterExtraction(Frame& f, StageContext& ctx) {
  trace_.FrameCount("extract", "keypoints", static_cast<int64_t>(f.N()));
  session_.Run(Hook::kAfterExtraction, ctx);
  session_.Run(Hook::kBeforeInitialPose, ctx);
  if (f.ExcludedCount() == static_cast<int>(f.N()) && f.N() > 0) ++n_all_excluded_;
}

// Map initialisation (ORB-SLAM2 StereoInitialization): the first keyframe, or not yet.
FrameLoop::TrackOutcome FrameLoop::Initialise(Frame& f) {
  TrackOutcome t;
  t.new_kf = tracker_.TryInitialise(f);
  t.ok = t.new_kf != nullptr;
  if (t.ok) trace_.FramePose("initial", f.T_cw.inverse());
  else t.lost_reason = "not-initialised";
  return t;
}

// ORB-SLAM2 Tracking::Track once initialised: initial pose, local map search, final pose, with
// the method's stages between them, then the keyframe decision.
FrameLoop::TrackOutcome FrameLoop::Track(Frame& f, StageContext& ctx) {
  TrackOutcome t;
  if (!tracker_.TrackInitial(f)) {
    t.lost_reason = ctx.lost ? "lost: relocalisation failed" : "lost: initial pose failed";
    return t;
  }
  trace_.FramePose("initial", f.T_cw.inverse());
  ctx.reference_kf = tracker_.reference_kf();
  session_.Run(Hook::kAfterInitialPose, ctx);
  tracker_.SearchLocalMap(f);
  ctx.reference_kf = tracker_.reference_kf();
  session_.Run(Hook::kBeforeFinalPose, ctx);
  t.ok = tracker_.OptimizeFinal(f);
  if (!t.ok) {
    t.lost_reason = "lost: local map tracking failed";
    return t;
  }
  t.new_kf = DecideKeyFrame(f);
  return t;
}

KeyFrame* FrameLoop::DecideKeyFrame(Frame& f) {
  // Oracle: the virtual mapping clock says whether local mapping is busy; concurrent: the
  // mapping thread itself (ORB-SLAM2's AcceptKeyFrames / KeyframesInQueue).
  const mapping::MappingLoad load = concurrent_
                                        ? mapping::MappingLoad{!mapper_busy_ && queue_.empty(), static_cast<int>(queue_.size())}
                                        : mapping_clock_.LoadAt(f.stamp);
  trace_.FrameCount("mapping", "idle", load.idle ? 1 : 0);
  trace_.FrameCount("mapping", "queued", load.queued);
  if (!tracker_.NeedNewKeyFrame(f, load.idle, load.queued, clock_options_max_queue_)) return nullptr;
  return tracker_.CreateNewKeyFrame(f);
}

// The on_keyframe_created stages and map modules, then local mapping: queued for the mapping
// thread (concurrent) or at once (oracle).
double FrameLoop::HandOverKeyFrame(Frame& f, KeyFrame& kf, StageContext& ctx) {
  FrameEdit kf_edit(kf.frame, map_, Hook::kOnKeyFrameCreated);
  ctx.new_keyframe = &kf;
  ctx.new_keyframe_edit = &kf_edit;
  ctx.reference_kf = tracker_.reference_kf();
  session_.Run(Hook::kOnKeyFrameCreated, ctx);
  const MapModuleContext mctx{f, kf, map_, camera_, trace_, options_.threads};
  session_.OnKeyFrame(mctx);
  double ba_ms = 0;
  if (concurrent_) {
    queue_.push_back(kf.id);
    queue_cv_.notify_one();
  } else {
    ba_ms = MapKeyFrameNow(f, kf, ctx, mctx);
  }
  ctx.new_keyframe_edit = nullptr;
  return ba_ms;
}

double FrameLoop::MapKeyFrameNow(const Frame& f, KeyFrame& kf, StageContext& ctx, const MapModuleContext& mctx) {
  const mapping::LocalMapperStats ms = mapper_.ProcessKeyFrame(kf.id);
  const double cost_ms = mapping_clock_.Charge(f.stamp, ms);
  trace_.FrameCount("mapping", "virtual_cost_us", static_cast<int64_t>(std::llround(cost_ms * 1e3)));
  session_.Run(Hook::kOnMapUpdate, ctx);
  AfterLocalMapping(kf, mctx);
  return ms.ba_ms;
}

// After local mapping of a keyframe (either thread): map modules, place index, loop closing.
void FrameLoop::AfterLocalMapping(KeyFrame& kf, const MapModuleContext& mctx) {
  session_.OnMapUpdate(mctx);
  if (place_ != nullptr) place_->AddAfterMapping(kf, map_);
  if (loop_ != nullptr) loop_->Process(kf.id, *place_);
}

void FrameLoop::EndFrame(Frame& f, const TrackOutcome& t) {
  trace_.FrameCount("features", "excluded", f.ExcludedCount());
  trace_.FrameCount("track", "ok", t.ok ? 1 : 0);
  trace_.FrameCount("track", "keyframe", t.new_kf != nullptr ? 1 : 0);
  tracker_.FinishFrame(f, t.ok);
}

void FrameLoop::CountFrame(size_t k, const TrackOutcome& t) {
  ++result_.frames;
  if (t.ok) ++result_.tracked;
  else lost_reasons_.emplace_back(static_cast<int>(k), t.lost_reason);
}

}  // namespace dynref
