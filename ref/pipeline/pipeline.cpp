// RunSequence: inputs, the method's Session, the frame loop, the outputs (pipeline.h).
#include "pipeline/pipeline.h"

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sha256.h"
#include "core/version.h"
#include "detect/detection_source.h"
#include "dynamic/builtin_methods.h"
#include "method/detection_tally.h"
#include "method/session.h"
#include "pipeline/frame_loop.h"
#include "pipeline/run_inputs.h"
#include "pipeline/run_outputs.h"
#include "render/overlay.h"

namespace dynref {
namespace {

namespace fs = std::filesystem;

trace::RunHeader MakeHeader(const RunOptions& options, const RunInputs& in) {
  trace::RunHeader header;
  header.dynref_version = DYNREF_VERSION;
  header.dynref_commit = DYNREF_GIT_COMMIT;
  header.method = in.config->method;
  header.config_json = in.config->ToJson();
  header.sequence_path = in.sequence_abs;
  header.detections_dir = in.detections_abs;
  for (const char* f : {"rgb.txt", "depth.txt", "camera.yaml"}) {
    const std::string p = options.sequence + "/" + f;
    if (fs::exists(p)) header.input_hashes.emplace_back(f, Sha256File(p));
  }
  header.detector_source = in.detector_name;
  const Camera& c = in.sequence.camera;
  nlohmann::json cam = {{"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}, {"bf", c.bf},
                        {"th_depth", c.th_depth}, {"width", c.width}, {"height", c.height},
                        {"depth_factor", c.depth_factor}, {"k1", c.k1}, {"k2", c.k2}, {"p1", c.p1},
                        {"p2", c.p2}, {"k3", c.k3}};
  header.extra.emplace_back("camera_json", cam.dump());  // trace verify back-projects with it
  return header;
}

// A run folder may replace an absent or empty folder or an earlier run (it has a run.json).
bool IsReplaceableRunFolder(const std::string& dir) {
  std::error_code ec;
  return IsAbsentOrEmptyDirectory(dir) || (fs::is_directory(dir, ec) && fs::exists(fs::path(dir) / "run.json", ec));
}

const char* kNotARunFolder = "exists and is not a dynref run folder (no run.json); refusing to replace it";

void ShowProgress(size_t k, size_t n, FrameLoop& loop) {
  std::cerr << "\rdynref run: frame " << (k + 1) << "/" << n << "  " << loop.ProgressLine() << "   " << std::flush;
}

}  // namespace

void RunOptions::Check() const {
  if (sequence.empty()) throw InputError("dynref run", "--sequence is required");
  if (out_dir.empty()) throw InputError("dynref run", "--out is required");
  CheckDirectoryPath(out_dir, "--out");
  trace::ParseLevel(trace_level);  // an unknown level is an error before anything is created
  if (!detector.empty()) {
    DetectSourceOptions d;
    d.sequence_root = sequence;
    CheckDetectionSpec(detector, d, "--detector");
  }
  try {
    detector_temporal.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError("--detector-temporal-gap/--detector-temporal-iou", e.what());
  }
  if (detector_temporal.max_gap > 0 && detector.empty())
    throw InputError("--detector-temporal-gap", "links a detector's frames: give --detector SPEC (a --detections "
                                                "folder is linked by dynref detect --temporal-gap)");
  if (threads < 1 || threads > 64) throw InputError("--threads", "must be in 1..64, got " + std::to_string(threads));
  if (variant != "oracle" && variant != "concurrent")
    throw InputError("--variant", "must be oracle or concurrent, got '" + variant + "'");
  if (frames.first < 0 || (!frames.open_ended() && frames.last < frames.first))
    throw InputError("dynref run", "--frames: need 0 <= A <= B");
  if (!detections_dir.empty() && !detector.empty())
    throw InputError("dynref run", "--detections and --detector are exclusive");
  if (overlays && trace_level != "full")
    throw InputError("dynref run", "--overlays needs --trace full (the overlays are drawn from its observation records)");
}

RunResult RunSequence(const RunOptions& options) {
  options.Check();
  // ---- inputs and the method's components (bad input here throws: exit 2, nothing written) ----
  RunInputs inputs = OpenRunInputs(options);
  MethodRegistry builtin;
  if (options.registry == nullptr) RegisterBuiltinMethods(builtin);
  Session session(inputs.config->path, inputs.config->stages, options.registry ? *options.registry : builtin);
  OpenDetections(options, inputs);

  // ---- the run folder is a unit: written in a staging folder, locked against a second writer,
  // renamed onto --out only when every output is closed (a killed or failed run leaves the
  // earlier folder as it was, and no mix of two runs) ----
  const std::string target = StagingDirectory::NormalisedTarget(options.out_dir);
  if (!IsReplaceableRunFolder(target)) throw InputError("--out", options.out_dir + " " + kNotARunFolder);
  StagingDirectory staging(target);
  const OutputLock lock(target, "--out");
  RemoveStaleTemps(target);  // staging folders of killed runs into the same --out
  const std::string dir = staging.dir();
  trace::TraceWriter trace(dir + "/trace.dtr", trace::ParseLevel(options.trace_level), MakeHeader(options, inputs));

  // ---- frames ----
  FrameLoop loop(options, inputs, session, trace);
  RunResult& result = loop.result();
  const size_t n = inputs.frames.size();
  if (n < 2) {
    result.end_state = "error: sequence has " + std::to_string(n) + " frame(s), need at least 2";
    result.exit_code = kExitBadInput;
  }
  const bool progress = options.progress && isatty(STDERR_FILENO);
  for (size_t k = 0; k < n && result.exit_code == 0; ++k) {
    if (!loop.Process(k)) {
      std::cerr << (progress ? "\n" : "") << "dynref run: " << result.end_state << "\n";
      break;
    }
    if (progress) ShowProgress(k, n, loop);
  }
  if (progress) std::cerr << "\n";
  loop.Drain();  // --variant concurrent: local mapping finishes its queue (a mapping error ends the run)
  if (result.exit_code != 0 && !result.end_state.empty()) std::cerr << "dynref run: " << result.end_state << "\n";

  // ---- outputs: the components' files, trajectories, the trace, then run.json ----
  const SessionEnd end = session.Finish(loop.map(), dir);
  WriteTrajectoryFiles(dir, inputs, loop);
  if (!end.errors.empty() && result.exit_code == 0) {
    result.end_state = "error: output " + end.errors.front();
    result.exit_code = kExitBadInput;
  }
  for (const std::string& e : end.errors) std::cerr << "dynref run: output " << e << "\n";
  for (const DetectionUse& u : end.detection_use) {  // issue 39: the end-of-run line and warnings
    result.detections_summary += (result.detections_summary.empty() ? "" : "; ") + DetectionUseText(u);
    if (u.MostDropped()) std::cerr << "dynref run: warning: " << DetectionUseWarning(u) << "\n";
  }
  try {
    trace.Close(result.end_state);
  } catch (const std::exception& e) {  // run.json must not call a run complete without its trace
    if (result.exit_code == 0) result.end_state = std::string("error: trace: ") + e.what();
    result.exit_code = kExitBadInput;
    std::cerr << "dynref run: trace: " << e.what() << "\n";
  }
  WriteRunJson(options, inputs, loop, end, dir);
  if (options.overlays && result.frames > 0) {
    render::OverlayOptions ro;
    ro.out_dir = dir + "/overlays";
    render::RenderRunOverlays(dir, inputs.frames.front().index, inputs.frames[result.frames - 1].index, ro);
  }
  PublishDirectory(dir, FailedRunTarget(target, options.out_dir, result), options.out_dir, IsReplaceableRunFolder,
                   kNotARunFolder);
  staging.Commit();
  return result;
}

}  // namespace dynref
