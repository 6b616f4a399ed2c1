#include "pipeline/run_inputs.h"

#include <filesystem>

#include "core/error.h"
#include "core/format.h"
#include "detect/temporal_source.h"
#include "map/frame.h"

namespace dynref {
namespace {

namespace fs = std::filesystem;

std::string AbsolutePath(const std::string& path) {
  return path.empty() ? path : fs::absolute(path).lexically_normal().string();
}

}  // namespace

RunInputs OpenRunInputs(const RunOptions& options) {
  RunInputs in;
  if (options.config) {
    in.config = options.config;
  } else {
    const std::string path = options.config_path.empty() ? MethodConfigPath(options.method) : options.config_path;
    in.config = std::make_shared<const MethodConfig>(LoadMethodConfig(path));
    if (!options.config_path.empty() && in.config->method != options.method && options.method != "orb")
      throw InputError(path, "config is for method '" + in.config->method + "', not '" + options.method + "'");
  }
  SequenceOptions seq_opts;
  seq_opts.camera = options.camera;
  in.sequence = OpenSequence(options.sequence, seq_opts);
  // ORB extraction keeps a 19 px border (EDGE_THRESHOLD) at the finest level and a 30 px cell
  // grid: a smaller image ended in a raw OpenCV assertion (issue 20 item 10, a 1 x 1 camera).
  const Camera& cam = in.sequence.camera;
  if (cam.width < 64 || cam.height < 48)
    throw InputError(cam.name, "camera image " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                                   " is too small for ORB extraction (dynref run needs at least 64x48)");
  return in;
}

void OpenDetections(const RunOptions& options, RunInputs& in) {
  if (!options.detections_dir.empty()) {
    in.det_reader = std::make_unique<DetectionsReader>(options.detections_dir);
    in.detector_name = in.det_reader->source() + " sha256:" + in.det_reader->model_sha256();
  } else if (!options.detector.empty()) {
    DetectSourceOptions dopt;
    dopt.sequence_root = options.sequence;
    in.det_source = MakeDetectionSource(options.detector, dopt);
    in.detector_name = in.det_source->name() + " sha256:" + in.det_source->model_sha256();
    const detect::TemporalOptions& t = options.detector_temporal;
    if (t.max_gap > 0) {
      const Camera& cam = in.sequence.camera;
      in.det_source = detect::WithTemporalLinks(std::move(in.det_source), t, cv::Size(cam.width, cam.height));
      in.detector_name += " temporal-gap:" + std::to_string(t.max_gap) + " temporal-iou:" + FormatDouble17(t.iou_link);
    }
  }
  // --frames must lie inside the sequence (same rule as detect and overlay).
  const int64_t last_frame = options.frames.LastIn(static_cast<int64_t>(in.sequence.frames.size()));
  for (const FrameEntry& e : in.sequence.frames)
    if (e.index >= options.frames.first && e.index <= last_frame) in.frames.push_back(e);
  in.sequence_abs = AbsolutePath(options.sequence);
  in.detections_abs = AbsolutePath(options.detections_dir);
}

void RunInputs::LoadFrame(const FrameEntry& e, const RunOptions& options, Frame& f, FrameDetections& dets) const {
  f.rgb = LoadRgb(sequence, e);
  f.depth_m = LoadDepthMeters(sequence, e);
  const Camera& camera = sequence.camera;
  if (det_reader) {
    if (!det_reader->Has(e.rgb_stamp_text))
      throw InputError(options.detections_dir, "no detections for frame stamp " + e.rgb_stamp_text);
    dets = det_reader->Read(e.rgb_stamp_text, cv::Size(camera.width, camera.height));
  } else if (det_source) {
    dets = det_source->Detect(f.rgb, e.rgb_stamp_text);
    dets.source = det_source->name();  // the scores' scale (detect/score_calibration.h)
  }
  if (det_reader || det_source) f.detections = &dets;
}

}  // namespace dynref
