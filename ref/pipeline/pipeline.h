// `dynref run`: the frame loop of the backbone with the method's stages at their hooks
// (method/hooks.h), sequential local mapping, and the run outputs:
//   RUN/trajectory.txt  every tracked frame, TUM format, T_wc (ORB-SLAM2 SaveTrajectoryTUM:
//                       frame pose relative to its reference keyframe, composed with the final
//                       keyframe pose)
//   RUN/lost.txt        frames without a pose: "<index> <stamp> <reason>"
//   RUN/keyframes.txt   keyframes (not culled), TUM format, T_wc
//   RUN/run.json        sequence, method, detections, resolved config, counts, tracking rate,
//                       per-module ms/frame, outputs of the method's components, end_state
//   RUN/trace.dtr       trace (ref/trace), unless --trace off
//   RUN/overlays/       with --overlays: one PNG per processed frame (ref/render)
#pragma once
#include <memory>
#include <string>

#include "core/frame_range.h"
#include "detect/temporal_links.h"
#include "method/registry.h"
#include "pipeline/method_config.h"

namespace dynref {

struct RunOptions {
  std::string sequence;
  std::string out_dir;
  std::string method = "orb";
  std::string config_path;       // empty: configs/<method>.yaml
  std::string trace_level = "frames";
  std::string detections_dir;    // dynref-detections folder (optional)
  std::string detector;          // detection source spec (ref/detect), optional
  // --detector-temporal-gap / --detector-temporal-iou: the detector's frames pass through the
  // temporal linker of `dynref detect --temporal-gap` (issue 39; max_gap 0 = off, the default).
  detect::TemporalOptions detector_temporal{0};
  std::string camera;            // preset / YAML; empty = auto
  FrameRange frames;             // --frames: inclusive sequence indices (default: all)
  bool progress = true;          // progress line when stderr is a terminal
  bool overlays = false;         // render RUN/overlays/ after the run (ref/render; needs a trace)
  // --threads: work that stays bit-identical runs on up to this many threads (issue 18; the list
  // is in reports/threads_bench.md). Results and traces do not depend on it; with > 1
  // the module timings in run.json are wall-clock ms (a thread's CPU clock misses its helpers).
  int threads = 1;
  // --variant: "oracle" (default: single-threaded, deterministic) or "concurrent" (issue 18:
  // local mapping in its own thread as in ORB-SLAM2, so results change from run to run; diff it
  // against the oracle with `dynref diff ORACLE CONCURRENT --summary`).
  std::string variant = "oracle";
  // In-memory config (e.g. a sweep that changed one parameter); when set, config_path and the
  // method's default config are not read.
  std::shared_ptr<const MethodConfig> config;
  // Stages and map modules available to the config; nullptr = every built-in method.
  const MethodRegistry* registry = nullptr;
  void Check() const;            // InputError naming the bad field
};

// End state of a run in which no frame had enough features with depth to start (a method's
// result, unlike a sequence whose depth is zero everywhere).
inline constexpr const char* kEndStateTooFewFeatures = "never-initialised: no frame had enough features with depth";

struct RunResult {
  std::string end_state;         // "complete", "lost-at-end", "never-initialised", "error: ..."
  int exit_code = 0;             // 0 ok, 2 bad input (see ExitCode)
  int frames = 0, tracked = 0, lost = 0, keyframes = 0;
  std::string detections_summary;  // per thresholding stage: seen / dropped detections (issue 39)
};

// Runs the whole sequence; writes every output atomically. Bad input found before the first
// frame throws InputError; bad input mid-run ends the run cleanly (result.end_state says why).
RunResult RunSequence(const RunOptions& options);

}  // namespace dynref
