// A frame's trace records after tracking and its module timings (FrameLoop, frame_loop.h).
#include "core/rng.h"  // Fnv1a64
#include "pipeline/frame_loop.h"

namespace dynref {

// The final pose, every feature's observation (full trace) and the structure residual counts.
void FrameLoop::TraceTrackedFrame(const Frame& f, bool ok) {
  if (ok) trace_.FramePose("final", f.T_cw.inverse());
  if (trace_.full_enabled()) TraceObservations(f);
  if (structure_ != nullptr) TraceStructure(f, ok);
}

void FrameLoop::TraceObservations(const Frame& f) {
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

void FrameLoop::TraceStructure(const Frame& f, bool ok) {
  structure_->TraceFrame(f);
  int lines = 0, planes = 0;
  for (size_t i = 0; i < f.structure.map_line_ids.size(); ++i) lines += f.structure.map_line_ids[i] >= 0;
  for (size_t j = 0; j < f.structure.map_plane_ids.size(); ++j) planes += f.structure.map_plane_ids[j] >= 0;
  trace_.FrameCount("structure.final", "line_residuals", ok ? lines : 0);
  trace_.FrameCount("structure.final", "plane_residuals", ok ? planes : 0);
}

// Module times of one frame (run.json only): tracking is the time before and after mapping,
// mapping excludes local BA.
void FrameLoop::RecordTimings(const FrameTimes& t) {
  timings_.load.push_back(t.loaded - t.start);
  timings_.extraction.push_back(t.extracted - t.loaded);
  timings_.tracking.push_back((t.tracked - t.extracted) + (t.finished - t.mapped));
  timings_.mapping.push_back((t.mapped - t.tracked) - t.ba_ms);
  timings_.ba.push_back(t.ba_ms);
  timings_.slam.push_back(t.finished - t.loaded);
  timings_.total.push_back(t.finished - t.start);
  if (structure_ != nullptr) timings_.lines.push_back(t.lines_ms), timings_.planes.push_back(t.planes_ms);
}

}  // namespace dynref
