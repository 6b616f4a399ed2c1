#include "pipeline/run_outputs.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/version.h"
#include "io/trajectory.h"
#include "method/detection_tally.h"

namespace dynref {
namespace {

// Median, 95th percentile (nearest rank) and mean over the run; mean over the first and the last
// min(100, n / 2) frames (issue 18: does the cost per frame grow with the sequence?).
nlohmann::json Summary(std::vector<double> v) {
  nlohmann::json j;
  if (v.empty()) return j;
  double sum = 0;
  for (double x : v) sum += x;
  const size_t window = std::min<size_t>(100, v.size() / 2);
  if (window > 0) {
    double head = 0, tail = 0;
    for (size_t i = 0; i < window; ++i) head += v[i], tail += v[v.size() - 1 - i];
    j["head_tail_frames"] = window;
    j["head_mean_ms_per_frame"] = head / static_cast<double>(window);
    j["tail_mean_ms_per_frame"] = tail / static_cast<double>(window);
  }
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  j["median_ms_per_frame"] = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  j["p95_ms_per_frame"] = v[std::min(n - 1, (95 * n + 99) / 100 - 1)];
  j["mean_ms_per_frame"] = sum / n;
  return j;
}

}  // namespace

void WriteTrajectoryFiles(const std::string& out_dir, const RunInputs& inputs, FrameLoop& loop) {
  const Map& map = loop.map();
  const auto& records = loop.tracker().records();
  std::vector<StampedPose> traj;
  for (const tracking::FrameRecord& r : records) {
    if (r.lost) continue;
    const SE3 T_cw = r.T_cr * map.ResolvedT_cw(r.ref_kf);
    traj.push_back({r.stamp, T_cw.inverse()});
  }
  std::vector<StampedPose> kfs;
  for (const auto& [id, kf] : map.keyframes) {
    (void)id;
    if (!kf->bad) kfs.push_back({kf->stamp, kf->T_cw.inverse()});
  }
  WriteTumTrajectory(out_dir + "/trajectory.txt", traj);
  WriteTumTrajectory(out_dir + "/keyframes.txt", kfs);
  AtomicOutputFile lost(out_dir + "/lost.txt");
  lost.stream() << "# frames without a pose: index stamp reason\n";
  for (const auto& [pos, reason] : loop.lost_reasons())
    lost.stream() << inputs.frames[pos].index << " " << inputs.frames[pos].rgb_stamp_text << " " << reason << "\n";
  lost.Commit();

  RunResult& result = loop.result();
  result.lost = static_cast<int>(loop.lost_reasons().size());
  for (const auto& kv : map.keyframes) result.keyframes += kv.second->bad ? 0 : 1;
  if (result.end_state.empty()) {
    if (result.tracked == 0) {
      result.end_state = loop.frames_zero_depth() == result.frames
                             ? "never-initialised: depth is zero in every frame"
                             : kEndStateTooFewFeatures;
      result.exit_code = kExitBadInput;
    } else if (!records.empty() && records.back().lost) {
      result.end_state = "lost-at-end";
    } else {
      result.end_state = "complete";
    }
  }
}

void WriteRunJson(const RunOptions& options, const RunInputs& inputs, FrameLoop& loop, const SessionEnd& end,
                  const std::string& dir) {
  const MethodConfig& cfg = *inputs.config;
  const Camera& camera = inputs.sequence.camera;
  const RunResult& result = loop.result();
  const ModuleTimings& t = loop.timings();
  nlohmann::json j;
  j["sequence"] = inputs.sequence_abs;
  j["method"] = cfg.method;
  j["detections"] = inputs.detections_abs;
  j["detector"] = inputs.detector_name;
  j["config"] = nlohmann::json::parse(cfg.ToJson());
  j["camera"] = {{"name", camera.name}, {"fx", camera.fx}, {"fy", camera.fy}, {"cx", camera.cx},
                 {"cy", camera.cy}, {"bf", camera.bf}, {"th_depth", camera.th_depth},
                 {"depth_factor", camera.depth_factor}};
  j["frames_in_sequence"] = inputs.sequence.frames.size();
  j["frames_processed"] = result.frames;
  j["frames_tracked"] = result.tracked;
  j["frames_lost"] = result.lost;
  j["frames_zero_depth"] = loop.frames_zero_depth();
  j["frames_all_features_excluded"] = loop.frames_all_excluded();
  j["tracking_rate"] = result.frames > 0 ? static_cast<double>(result.tracked) / result.frames : 0.0;
  j["keyframes"] = result.keyframes;
  // Every keyframe ever inserted (ids are never reused), culled ones included: per-keyframe costs of map
  // modules divide by this, since they ran once per inserted keyframe.
  j["keyframes_created"] = loop.map().next_kf_id();
  j["map_points"] = loop.map().GoodPointCount();
  j["local_ba_calls"] = loop.mapper().ba_calls();
  j["trace_level"] = options.trace_level;
  j["threads"] = options.threads;
  j["variant"] = options.variant;
  j["timing_clock"] =
      std::string(options.threads > 1 || options.variant == "concurrent"
                      ? "wall-clock time (CLOCK_MONOTONIC: --threads > 1 or --variant concurrent, whose other threads a "
                        "thread CPU clock misses; stages and lines/planes stay thread CPU time)"
                      : "thread CPU time (CLOCK_THREAD_CPUTIME_ID)") +
      ", ms per processed frame; load = PNG decoding (+ detections), "
      "extraction = grey + before_extraction stages + ORB + undistortion + depth lookup, tracking includes the "
      "method stages, slam = everything after load (ORB-SLAM2's TrackRGBD span plus the sequential local "
      "mapping), total = load + slam";
  j["timing"] = {{"load", Summary(t.load)}, {"extraction", Summary(t.extraction)}, {"tracking", Summary(t.tracking)},
                 {"local_mapping", Summary(t.mapping)}, {"ba", Summary(t.ba)},
                 {"slam", Summary(t.slam)}, {"total", Summary(t.total)}};
  if (!t.mapping_thread.empty())  // --variant concurrent: ms per keyframe in the local-mapping thread
    j["timing"]["mapping_thread_per_keyframe"] = Summary(t.mapping_thread);
  if (!t.lines.empty()) {  // lines / planes on (issue 13): parts of extraction
    j["timing"]["lines"] = Summary(t.lines);
    j["timing"]["planes"] = Summary(t.planes);
  }
  if (const loop::LoopCloser* lc = loop.loop_closer()) {  // backbone.loop_closing on (issue 34): its cost
    const loop::LoopTiming& lt = lc->timing();
    const double frames = result.frames > 0 ? double(result.frames) : 1.0;
    j["loop_closing"] = {{"keyframes_processed", lt.keyframes},
                         {"loops_closed", lt.loops},
                         {"detect_ms_per_frame", lt.detect_ms / frames},
                         {"detect_ms_per_keyframe", lt.keyframes > 0 ? lt.detect_ms / double(lt.keyframes) : 0.0},
                         {"correct_ms_per_loop", lt.loops > 0 ? lt.correct_ms / double(lt.loops) : 0.0},
                         {"global_ba_ms_per_loop", lt.loops > 0 ? lt.global_ba_ms / double(lt.loops) : 0.0},
                         {"total_ms_per_frame", (lt.detect_ms + lt.correct_ms + lt.global_ba_ms) / frames},
                         {"clock", "thread CPU time of the thread that ran loop closing; part of local_mapping"}};
  }
  j["map_lines"] = loop.map().GoodLineCount();
  j["map_planes"] = loop.map().GoodPlaneCount();
  // Per method stage, CPU ms per processed frame (the papers' runtime tables; part of the modules above).
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, ms] : loop.session().StageTimes())
    stages[name] = result.frames > 0 ? ms / result.frames : 0.0;
  j["timing_stages"] = stages;
  nlohmann::json outputs = nlohmann::json::array();
  for (const RunOutput& o : end.outputs) outputs.push_back({{"module", o.module}, {"path", o.path}, {"what", o.what}});
  j["outputs"] = outputs;
  j["output_errors"] = end.errors;
  // Issue 39: what each thresholding stage saw and dropped, and a warning when it dropped most.
  nlohmann::json used = nlohmann::json::array(), warnings = nlohmann::json::array();
  for (const DetectionUse& u : end.detection_use) {
    used.push_back({{"stage", u.stage}, {"key", u.key}, {"threshold_scale", u.scale}, {"source", u.source},
                    {"paper_threshold", u.paper_threshold}, {"applied_threshold", u.applied_threshold},
                    {"seen", u.seen}, {"dropped", u.dropped}});
    if (u.MostDropped()) warnings.push_back(DetectionUseWarning(u));
  }
  j["detections_used"] = used;
  j["warnings"] = warnings;
  j["end_state"] = result.end_state;
  j["dynref_version"] = DYNREF_VERSION;
  j["dynref_commit"] = DYNREF_GIT_COMMIT;
  // Paths and config sources are user text: invalid UTF-8 is written as U+FFFD, not an error.
  AtomicWriteFile(dir + "/run.json", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

std::string FailedRunTarget(const std::string& target, const std::string& shown, const RunResult& result) {
  std::error_code ec;
  if (result.exit_code == 0 || !std::filesystem::exists(std::filesystem::path(target) / "run.json", ec)) return target;
  const std::string failed = target + ".failed";
  std::cerr << "dynref run: " << shown << " keeps its earlier run; this failed attempt (run.json, trace.dtr) is in "
            << failed << "\n";
  return failed;
}

}  // namespace dynref
