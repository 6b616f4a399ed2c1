// The backbone frame loop; see pipeline.h and stage.h for the order of steps and hooks.
#include "pipeline/pipeline.h"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/rng.h"
#include "core/sha256.h"
#include "core/version.h"
#include "detect/detection_source.h"
#include "features/orb_extractor.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "io/trajectory.h"
#include "mapping/local_mapper.h"
#include "pipeline/method_config.h"
#include "pipeline/stage_registry.h"
#include "render/overlay.h"
#include "tracking/tracker.h"

namespace dynref {
namespace {

namespace fs = std::filesystem;

std::string AbsolutePath(const std::string& path) {
  return path.empty() ? path : fs::absolute(path).lexically_normal().string();
}

// Module timings use the thread's CPU clock (the run is single-threaded), so they measure the
// work done and not the load of the machine. They go to run.json only, never into results.
struct Clock {
  using time_point = double;
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  }
};

double Ms(double a, double b) { return b - a; }

struct Timings {
  std::vector<double> load, extraction, tracking, mapping, ba, slam, total;
};

nlohmann::json Summary(std::vector<double> v) {
  nlohmann::json j;
  if (v.empty()) return j;
  double sum = 0;
  for (double x : v) sum += x;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  j["median_ms_per_frame"] = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  j["mean_ms_per_frame"] = sum / n;
  return j;
}

void RunStages(std::vector<std::unique_ptr<Stage>>& stages, Hook hook, StageContext& ctx) {
  for (auto& s : stages)
    if (s->hook() == hook) s->Run(ctx);
}

}  // namespace

void RunOptions::Check() const {
  if (sequence.empty()) throw InputError("dynref run", "--sequence is required");
  if (out_dir.empty()) throw InputError("dynref run", "--out is required");
  CheckDirectoryPath(out_dir, "--out");
  if (!detector.empty()) {
    DetectSourceOptions d;
    d.sequence_root = sequence;
    CheckDetectionSpec(detector, d, "--detector");
  }
  if (frames.first < 0 || (!frames.open_ended() && frames.last < frames.first))
    throw InputError("dynref run", "--frames: need 0 <= A <= B");
  if (!detections_dir.empty() && !detector.empty())
    throw InputError("dynref run", "--detections and --detector are exclusive");
  if (overlays && trace_level != "full")
    throw InputError("dynref run", "--overlays needs --trace full (the overlays are drawn from its observation records)");
}

RunResult RunSequence(const RunOptions& options) {
  options.Check();
  // ---- configuration and inputs (bad input here throws: exit 2, nothing written) ----
  const std::string config_path = options.config_path.empty() ? MethodConfigPath(options.method) : options.config_path;
  const MethodConfig cfg = LoadMethodConfig(config_path);
  if (!options.config_path.empty() && cfg.method != options.method && options.method != "orb")
    throw InputError(config_path, "config is for method '" + cfg.method + "', not '" + options.method + "'");
  SequenceOptions seq_opts;
  seq_opts.camera = options.camera;
  const Sequence seq = OpenSequence(options.sequence, seq_opts);
  const Camera& camera = seq.camera;
  std::vector<std::unique_ptr<Stage>> stages = CreateStages(cfg, BuiltinStageRegistry());
  std::unique_ptr<DetectionsReader> det_reader;
  std::unique_ptr<DetectionSource> det_source;
  std::string detector_name = "none";
  if (!options.detections_dir.empty()) {
    det_reader = std::make_unique<DetectionsReader>(options.detections_dir);
    detector_name = det_reader->source() + " sha256:" + det_reader->model_sha256();
  } else if (!options.detector.empty()) {
    DetectSourceOptions dopt;
    dopt.sequence_root = options.sequence;
    det_source = MakeDetectionSource(options.detector, dopt);
    detector_name = det_source->name() + " sha256:" + det_source->model_sha256();
  }
  // --frames must lie inside the sequence (same rule as detect and overlay).
  const int64_t last_frame = options.frames.LastIn(static_cast<int64_t>(seq.frames.size()));
  std::vector<FrameEntry> frames;
  for (const FrameEntry& e : seq.frames)
    if (e.index >= options.frames.first && e.index <= last_frame) frames.push_back(e);
  fs::create_directories(options.out_dir);
  // A rerun into the same folder must not leave outputs of the earlier run beside the new ones.
  if (trace::ParseLevel(options.trace_level) == trace::Level::kOff)
    fs::remove(options.out_dir + "/trace.dtr");
  if (!options.overlays) fs::remove_all(options.out_dir + "/overlays");

  trace::RunHeader header;
  header.dynref_version = DYNREF_VERSION;
  header.dynref_commit = DYNREF_GIT_COMMIT;
  header.method = cfg.method;
  header.config_json = cfg.ToJson();
  // Absolute paths: overlays and reports open the run from any working directory.
  const std::string sequence_abs = AbsolutePath(options.sequence);
  const std::string detections_abs = AbsolutePath(options.detections_dir);
  header.sequence_path = sequence_abs;
  header.detections_dir = detections_abs;
  for (const char* f : {"rgb.txt", "depth.txt", "camera.yaml"}) {
    const std::string p = options.sequence + "/" + f;
    if (fs::exists(p)) header.input_hashes.emplace_back(f, Sha256File(p));
  }
  header.detector_source = detector_name;
  trace::TraceWriter trace(options.out_dir + "/trace.dtr", trace::ParseLevel(options.trace_level), header);

  RunResult result;
  std::vector<std::pair<int, std::string>> lost_reasons;  // frame position -> reason
  if (frames.size() < 2) {
    result.end_state = "error: sequence has " + std::to_string(frames.size()) + " frame(s), need at least 2";
    result.exit_code = kExitBadInput;
  }

  // ---- backbone ----
  features::OrbOptions orb;
  orb.n_features = cfg.backbone.n_features();
  orb.scale_factor = cfg.backbone.scale_factor();
  orb.n_levels = cfg.backbone.n_levels();
  orb.ini_th_fast = cfg.backbone.ini_th_fast();
  orb.min_th_fast = cfg.backbone.min_th_fast();
  features::OrbExtractor extractor(orb);
  const ScalePyramid pyramid = ScalePyramid::Make(orb.n_levels, orb.scale_factor);
  Map map;
  tracking::TrackerOptions topt;
  topt.min_init_points = cfg.backbone.min_init_points();
  topt.max_frames = cfg.backbone.max_frames();
  topt.reloc_recent_keyframes = cfg.backbone.reloc_recent_keyframes();
  topt.seed = cfg.backbone.seed();
  const bool rgb_flag = cfg.backbone.camera_rgb_flag();
  tracking::Tracker tracker(camera, map, topt, trace);
  mapping::LocalMapperOptions mopt;
  mopt.local_ba = cfg.backbone.local_ba();
  mopt.keyframe_culling = cfg.backbone.keyframe_culling();
  mapping::LocalMapper mapper(map, camera, mopt, trace);

  Timings timings;
  const bool progress = options.progress && isatty(STDERR_FILENO);
  int n_zero_depth = 0, n_all_excluded = 0;
  for (size_t k = 0; k < frames.size() && result.exit_code == 0; ++k) {
    const FrameEntry& e = frames[k];
    trace.BeginFrame(e.index, e.rgb_stamp);
    const auto t0 = Clock::now();
    Frame f;
    f.index = e.index;
    f.stamp = e.rgb_stamp;
    f.stamp_text = e.rgb_stamp_text;
    f.trace = &trace;
    FrameDetections dets;
    // Bad input mid-run (an unreadable frame, a detection mask of the wrong size, a stage
    // rejecting its input) ends the run cleanly: the outputs so far are written and run.json
    // says where and why.
    try {
      f.rgb = LoadRgb(seq, e);
      f.depth_m = LoadDepthMeters(seq, e);
      if (det_reader) {
        if (!det_reader->Has(e.rgb_stamp_text))
          throw InputError(options.detections_dir, "no detections for frame stamp " + e.rgb_stamp_text);
        dets = det_reader->Read(e.rgb_stamp_text, cv::Size(camera.width, camera.height));
      } else if (det_source) {
        dets = det_source->Detect(f.rgb, e.rgb_stamp_text);
      }
      if (det_reader || det_source) f.detections = &dets;
      const auto t_loaded = Clock::now();
      // f.rgb is BGR (cv::imread). ORB-SLAM2's rgbd_tum with Camera.RGB: 1 (TUM1-3.yaml) converts
      // those BGR images with CV_RGB2GRAY, so blue gets red's weight; backbone.camera_rgb_flag
      // reproduces that grey image (default), false gives the true luminance.
      cv::cvtColor(f.rgb, f.grey, rgb_flag ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
      if (cv::countNonZero(f.depth_m > 0) == 0) ++n_zero_depth;
      extractor.Extract(f.grey, &f.keys, &f.descriptors);
      f.pyramid = pyramid;
      f.FinishFeatures(camera);
      const auto t1 = Clock::now();
      trace.FrameCount("extract", "keypoints", static_cast<int64_t>(f.N()));

      const Frame* prev = tracker.last_frame();
      const bool was_lost = tracker.state() == tracking::TrackState::kLost;
      const bool initialised = tracker.state() != tracking::TrackState::kNotInitialised;
      StageContext ctx{f,           prev,   tracker.reference_kf(), map, camera, trace, nullptr,
                       nullptr,     initialised, was_lost, options.out_dir};
      RunStages(stages, Hook::kAfterExtraction, ctx);
      RunStages(stages, Hook::kBeforeInitialPose, ctx);
      if (f.ExcludedCount() == static_cast<int>(f.N()) && f.N() > 0) ++n_all_excluded;

      bool ok = false;
      KeyFrame* new_kf = nullptr;
      double mapping_ms = 0, ba_ms = 0;
      std::string lost_reason;
      if (!initialised) {
        new_kf = tracker.TryInitialise(f);
        ok = new_kf != nullptr;
        if (!ok) lost_reason = "not-initialised";
        if (ok) trace.FramePose("initial", f.T_cw.inverse());
      } else {
        ok = tracker.TrackInitial(f);
        if (ok) {
          trace.FramePose("initial", f.T_cw.inverse());
          ctx.reference_kf = tracker.reference_kf();
          RunStages(stages, Hook::kAfterInitialPose, ctx);
          tracker.SearchLocalMap(f);
          ctx.reference_kf = tracker.reference_kf();
          RunStages(stages, Hook::kBeforeFinalPose, ctx);
          ok = tracker.OptimizeFinal(f);
          if (!ok) lost_reason = "lost: local map tracking failed";
        } else {
          lost_reason = was_lost ? "lost: relocalisation failed" : "lost: initial pose failed";
        }
        if (ok && tracker.NeedNewKeyFrame(f)) new_kf = tracker.CreateNewKeyFrame(f);
      }
      const auto t2 = Clock::now();
      if (ok) trace.FramePose("final", f.T_cw.inverse());
      if (trace.full_enabled()) {
        for (size_t i = 0; i < f.N(); ++i) {
          const cv::KeyPoint& kp = f.keys_un[i];
          const int64_t mp = f.outlier[i] ? -1 : f.map_point_ids[i];
          trace.Observation(static_cast<int64_t>(i), mp, kp.pt.x, kp.pt.y, f.depth[i] > 0 ? f.depth[i] : 0.0,
                            kp.octave, Fnv1a64(f.descriptors.ptr<uint8_t>(static_cast<int>(i)), 32));
        }
      }
      if (new_kf != nullptr) {
        ctx.new_keyframe = new_kf;
        ctx.mutable_map = &map;
        ctx.reference_kf = tracker.reference_kf();
        RunStages(stages, Hook::kOnKeyFrameCreated, ctx);
        const mapping::LocalMapperStats ms = mapper.ProcessKeyFrame(new_kf->id);
        ba_ms = ms.ba_ms;
        RunStages(stages, Hook::kOnMapUpdate, ctx);
      }
      const auto t3 = Clock::now();
      mapping_ms = Ms(t2, t3) - ba_ms;
      trace.FrameCount("features", "excluded", f.ExcludedCount());
      trace.FrameCount("track", "ok", ok ? 1 : 0);
      trace.FrameCount("track", "keyframe", new_kf != nullptr ? 1 : 0);
      tracker.FinishFrame(f, ok);
      const auto t4 = Clock::now();
      timings.load.push_back(Ms(t0, t_loaded));
      timings.extraction.push_back(Ms(t_loaded, t1));
      timings.tracking.push_back(Ms(t1, t2) + Ms(t3, t4));
      timings.mapping.push_back(mapping_ms);
      timings.ba.push_back(ba_ms);
      timings.slam.push_back(Ms(t_loaded, t4));
      timings.total.push_back(Ms(t0, t4));
      ++result.frames;
      if (ok) ++result.tracked;
      else lost_reasons.emplace_back(static_cast<int>(k), lost_reason);
      if (progress) {
        std::cerr << "\rdynref run: frame " << (k + 1) << "/" << frames.size() << "  keyframes "
                  << map.keyframes.size() << "  points " << map.GoodPointCount() << "  lost "
                  << lost_reasons.size() << "   " << std::flush;
      }
    } catch (const std::exception& err) {
      result.end_state = "error: frame " + std::to_string(e.index) + " (" + e.rgb_stamp_text + "): " + err.what();
      result.exit_code = kExitBadInput;
      std::cerr << (progress ? "\n" : "") << "dynref run: " << result.end_state << "\n";
      break;
    }
  }
  if (progress) std::cerr << "\n";

  // ---- outputs ----
  const auto& records = tracker.records();
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
  WriteTumTrajectory(options.out_dir + "/trajectory.txt", traj);
  WriteTumTrajectory(options.out_dir + "/keyframes.txt", kfs);
  {
    AtomicOutputFile lost(options.out_dir + "/lost.txt");
    lost.stream() << "# frames without a pose: index stamp reason\n";
    for (const auto& [pos, reason] : lost_reasons)
      lost.stream() << frames[pos].index << " " << frames[pos].rgb_stamp_text << " " << reason << "\n";
    lost.Commit();
  }
  result.lost = static_cast<int>(lost_reasons.size());
  for (const auto& kv : map.keyframes) result.keyframes += kv.second->bad ? 0 : 1;
  if (result.end_state.empty()) {
    if (result.tracked == 0) {
      result.end_state = n_zero_depth == result.frames ? "never-initialised: depth is zero in every frame"
                                                       : "never-initialised: no frame had enough features with depth";
      result.exit_code = kExitBadInput;
    } else if (!records.empty() && records.back().lost) {
      result.end_state = "lost-at-end";
    } else {
      result.end_state = "complete";
    }
  }

  nlohmann::json j;
  j["sequence"] = sequence_abs;
  j["method"] = cfg.method;
  j["detections"] = detections_abs;
  j["detector"] = detector_name;
  j["config"] = nlohmann::json::parse(cfg.ToJson());
  j["camera"] = {{"name", camera.name}, {"fx", camera.fx}, {"fy", camera.fy}, {"cx", camera.cx},
                 {"cy", camera.cy}, {"bf", camera.bf}, {"th_depth", camera.th_depth},
                 {"depth_factor", camera.depth_factor}};
  j["frames_in_sequence"] = seq.frames.size();
  j["frames_processed"] = result.frames;
  j["frames_tracked"] = result.tracked;
  j["frames_lost"] = result.lost;
  j["frames_zero_depth"] = n_zero_depth;
  j["frames_all_features_excluded"] = n_all_excluded;
  j["tracking_rate"] = result.frames > 0 ? static_cast<double>(result.tracked) / result.frames : 0.0;
  j["keyframes"] = result.keyframes;
  j["map_points"] = map.GoodPointCount();
  j["local_ba_calls"] = mapper.ba_calls();
  j["trace_level"] = options.trace_level;
  j["timing_clock"] = "thread CPU time (CLOCK_THREAD_CPUTIME_ID), ms per processed frame; load = PNG decoding (+ detections), extraction = grey + ORB + undistortion + depth lookup, tracking includes the method stages, slam = everything after load (ORB-SLAM2's TrackRGBD span plus the sequential local mapping), total = load + slam";
  j["timing"] = {{"load", Summary(timings.load)}, {"extraction", Summary(timings.extraction)}, {"tracking", Summary(timings.tracking)},
                 {"local_mapping", Summary(timings.mapping)}, {"ba", Summary(timings.ba)},
                 {"slam", Summary(timings.slam)}, {"total", Summary(timings.total)}};
  j["end_state"] = result.end_state;
  j["dynref_version"] = DYNREF_VERSION;
  j["dynref_commit"] = DYNREF_GIT_COMMIT;
  // Paths and config sources are user text: invalid UTF-8 is written as U+FFFD, not an error.
  AtomicWriteFile(options.out_dir + "/run.json",
                  j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  trace.Close(result.end_state);
  if (options.overlays && result.frames > 0) {
    render::OverlayOptions ro;
    ro.out_dir = options.out_dir + "/overlays";
    render::RenderRunOverlays(options.out_dir, frames.front().index, frames[result.frames - 1].index, ro);
  }
  return result;
}

}  // namespace dynref
