// `dynref detect`: precomputes per-frame detections of a sequence (or one image) into dynref's
// mask format (datasets/MASK_FORMAT.md), so a run is reproducible and the network runs once.
//   dynref detect --source nanodet --sequence SEQ --out DIR [--model PATH] [--conf X] [--frames A-B]
//   dynref detect --source nanodet --image photo.jpg --overlay out.png
// Sources: ref/detect/README.md.
#include <chrono>
#include <filesystem>
#include <cmath>
#include <ctime>
#include <iostream>
#include <map>
#include <sstream>
#include <sys/stat.h>

#include "cli/command.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/frame_range.h"
#include "core/format.h"
#include "core/version.h"
#include "detect/detection_source.h"
#include "detect/overlay.h"
#include "detect/temporal_links.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "io/image_file.h"

namespace dynref::cli {
namespace {

struct DetectArgs {
  std::string source, sequence, out, camera, input, mode, image, overlay, overlays, frames;
  DetectSourceOptions options;
  detect::TemporalOptions temporal{0};  // --temporal-gap 0: off (issue 39)
  bool no_masks = false;
  int repeat = 0;
  bool conf_given = false, frames_given = false;  // the option was on the command line
};

std::string SpecOf(const DetectArgs& a) {
  std::string spec = a.source;
  if ((spec == "files" || spec == "labels") && !a.input.empty()) spec += ":" + a.input;
  if (spec == "gt" && !a.mode.empty()) spec += ":" + a.mode;
  return spec;
}

// Every option checked before anything is opened; InputError names the option.
void CheckArgs(const DetectArgs& a) {
  const DetectSourceOptions& o = a.options;
  if (a.conf_given && !(o.confidence_threshold >= 0 && o.confidence_threshold <= 1))  // NaN fails too
    throw InputError("--conf", "must be in [0, 1], got " + FormatDouble17(o.confidence_threshold));
  if (!(o.nms_iou > 0 && o.nms_iou <= 1))
    throw InputError("--nms-iou", "must be in (0, 1], got " + FormatDouble17(o.nms_iou));
  if (o.max_detections < 1 || o.max_detections > 65535)
    throw InputError("--max-detections", "must be in 1..65535, got " + std::to_string(o.max_detections));
  if (o.yolo_input_size < 32 || o.yolo_input_size % 32 != 0)
    throw InputError("--input-size", "must be a positive multiple of 32, got " + std::to_string(o.yolo_input_size));
  if (a.frames_given && a.frames.empty())
    throw InputError("--frames", "empty value (give A, A-B or A-; omit --frames for all frames)");
  if (!a.frames.empty()) ParseFrameRange(a.frames);
  CheckDetectionSpec(SpecOf(a), o, "--source");
  try {
    a.temporal.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError("--temporal-gap/--temporal-iou", e.what());
  }
}

void WritePng(const std::string& path, const cv::Mat& image) {
  const std::string tmp = TempPathFor(path) + ".png";
  if (!dynref::ImageWrite(tmp, image)) throw InputError(path, "cannot write PNG");
  AtomicRename(tmp, path);
}

std::string Summary(const FrameDetections& f) {
  std::map<std::string, int> by_class;
  int masks = 0;
  for (const auto& d : f.instances) {
    ++by_class[d.class_name];
    masks += d.has_mask;
  }
  std::ostringstream o;
  o << f.instances.size() << " instances (" << masks << " masks)";
  for (const auto& [name, n] : by_class) o << " " << name << "x" << n;
  return o.str();
}

void PrintInstances(const FrameDetections& f) {
  for (const auto& d : f.instances)
    std::cout << "  " << d.id << " " << d.class_name << " conf " << FormatFixed(d.confidence, 3) << " box ["
              << FormatFixed(d.x_min, 1) << ", " << FormatFixed(d.y_min, 1) << ", " << FormatFixed(d.x_max, 1)
              << ", " << FormatFixed(d.y_max, 1) << "]" << (d.has_mask ? " mask" : "") << "\n";
}

std::string InfoText(const DetectArgs& a, const DetectionSource& src, size_t first, size_t last) {
  const DetectSourceOptions& o = a.options;
  std::ostringstream s;
  s << "# parameters of the `dynref detect` run that wrote this folder (no timings)\n"
    << "dynref " << DYNREF_VERSION << " " << DYNREF_GIT_COMMIT << "\n"
    << "source_spec " << SpecOf(a) << "\nsource " << src.name() << "\nmodel_sha256 " << src.model_sha256()
    << "\nmodel_path " << (o.model_path.empty() ? "-" : o.model_path) << "\nmask_model_path "
    << (o.mask_model_path.empty() ? "-" : o.mask_model_path) << "\nconfidence_threshold "
    << (o.confidence_threshold < 0 ? std::string("default") : FormatDouble17(o.confidence_threshold))
    << "\nnms_iou " << FormatDouble17(o.nms_iou) << "\nmax_detections " << o.max_detections << "\nmasks "
    << (o.masks ? 1 : 0) << "\nsequence " << a.sequence << "\nframes " << first << "-" << last << "\n";
  if (a.temporal.max_gap > 0)
    s << "temporal_gap " << a.temporal.max_gap << "\ntemporal_iou " << FormatDouble17(a.temporal.iou_link)
      << "\ntemporal_history " << a.temporal.history << "\n";
  return s.str();
}

// --out may be absent, empty, or an earlier dynref-detections folder (it has format.txt).
bool IsReplaceableDetections(const std::string& dir) {
  std::error_code ec;
  return IsAbsentOrEmptyDirectory(dir) ||
         (std::filesystem::is_directory(dir, ec) && std::filesystem::exists(std::filesystem::path(dir) / "format.txt", ec));
}
const char* kNotDetections = "exists and is not a dynref-detections folder (no format.txt); refusing to replace it";

int RunDetect(DetectArgs a) {
  a.options.masks = !a.no_masks;
  a.options.sequence_root = a.sequence;
  if (a.image.empty() == a.sequence.empty()) throw InputError("<args>", "give exactly one of --sequence or --image");
  if (!a.sequence.empty() && a.out.empty()) throw InputError("<args>", "--sequence needs --out DIR");
  if (!a.overlay.empty() && a.image.empty()) throw InputError("<args>", "--overlay goes with --image (use --overlays DIR)");
  CheckArgs(a);
  using Clock = std::chrono::steady_clock;

  if (!a.image.empty()) {
    auto source = MakeDetectionSource(SpecOf(a), a.options);
    const cv::Mat bgr = dynref::ImageRead(a.image, cv::IMREAD_COLOR);
    if (bgr.empty()) throw InputError(a.image, "cannot read image");
    std::string stem = a.image.substr(a.image.find_last_of('/') + 1);
    stem = stem.substr(0, stem.find_last_of('.'));
    FrameDetections f = source->Detect(bgr, stem);  // first call pays one-off allocations
    // --repeat N: N more timed runs of the same frame (a benchmark; output must not change).
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    for (int r = 0; r < a.repeat; ++r) f = source->Detect(bgr, stem);
    std::cout << a.image << " (" << bgr.cols << "x" << bgr.rows << "): " << Summary(f) << "\n";
    PrintInstances(f);
    if (a.repeat > 0)
      std::cerr << "time: " << FormatFixed(std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / a.repeat, 1)
                << " ms/frame wall, " << FormatFixed(1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / a.repeat, 1)
                << " ms/frame CPU over " << a.repeat << " repeats\n";
    if (!a.overlay.empty()) WritePng(a.overlay, detect::DrawDetections(bgr, f));
    if (!a.out.empty()) {
      DetectionsWriter w(a.out, source->name(), source->model_sha256());
      w.Write(f);
      w.Finish();
    }
    return kExitOk;
  }

  SequenceOptions so;
  so.camera = a.camera;
  const Sequence seq = OpenSequence(a.sequence, so);
  const FrameRange range = a.frames.empty() ? FrameRange{} : ParseFrameRange(a.frames);
  const size_t first = static_cast<size_t>(range.first);
  const size_t last = static_cast<size_t>(range.LastIn(static_cast<int64_t>(seq.frames.size())));
  auto source = MakeDetectionSource(SpecOf(a), a.options);  // after the cheap argument checks
  if (!a.overlays.empty()) {
    ::mkdir(a.overlays.c_str(), 0755);
  }
  // The output folder is a unit (issue 20 item 6): written in a staging folder and renamed onto
  // --out when every frame is written, replacing an earlier detections folder whole (a failed
  // rerun used to leave the old index.txt beside the new format.txt).
  const std::string target = StagingDirectory::NormalisedTarget(a.out);
  if (!IsReplaceableDetections(target))
    throw InputError("--out", a.out + " " + kNotDetections);
  StagingDirectory staging(target);
  const std::string out_dir = staging.dir();
  DetectionsWriter writer(out_dir, source->name(), source->model_sha256());
  std::map<std::string, int> totals;
  std::vector<double> wall_ms, cpu_ms;  // per frame
  // --temporal-gap N: tracks across frames; a missed person is carried N frames (tracks.txt).
  detect::TemporalLinker linker(a.temporal, cv::Size(seq.camera.width, seq.camera.height));
  std::ostringstream tracks;
  tracks << "# rgb_stamp instance_id track origin (detected | carried), dynref detect --temporal-gap "
         << a.temporal.max_gap << "\n";
  for (size_t i = first; i <= last; ++i) {
    const FrameEntry& fe = seq.frames[i];
    const bool need = source->needs_image() || !a.overlays.empty();
    const cv::Mat bgr = need ? LoadRgb(seq, fe) : cv::Mat();
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    FrameDetections f = source->Detect(bgr, fe.rgb_stamp_text);
    if (a.temporal.max_gap > 0) {
      std::vector<detect::TrackLink> links;
      f = linker.Process(f, fe.rgb_stamp, &links);
      for (const detect::TrackLink& l : links)
        tracks << fe.rgb_stamp_text << " " << l.instance_id << " " << l.track << " " << (l.carried ? "carried" : "detected")
               << "\n";
    }
    cpu_ms.push_back(1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC);
    wall_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    // Sources that never decode the frame (files:, labels:) are checked against the camera size
    // here (issue 20 item 7: 320x240 masks of a 640x480 sequence were accepted).
    if (!f.instance_ids.empty() && (f.instance_ids.cols != seq.camera.width || f.instance_ids.rows != seq.camera.height))
      throw InputError(a.source, "frame " + fe.rgb_stamp_text + ": mask is " + std::to_string(f.instance_ids.cols) + "x" +
                                     std::to_string(f.instance_ids.rows) + " but the sequence's camera is " +
                                     std::to_string(seq.camera.width) + "x" + std::to_string(seq.camera.height));
    writer.Write(f);
    for (const auto& d : f.instances) ++totals[d.class_name];
    std::cout << "frame " << fe.index << " " << fe.rgb_stamp_text << ": " << Summary(f) << "\n";
    if (!a.overlays.empty()) WritePng(a.overlays + "/" + fe.rgb_stamp_text + ".png", detect::DrawDetections(bgr, f));
  }
  writer.Finish();
  AtomicWriteFile(out_dir + "/detect_info.txt", InfoText(a, *source, first, last));
  if (a.temporal.max_gap > 0) AtomicWriteFile(out_dir + "/tracks.txt", tracks.str());
  PublishDirectory(out_dir, target, a.out, IsReplaceableDetections, kNotDetections);
  staging.Commit();
  const size_t n = last - first + 1;
  std::cout << "detect: " << n << " frames, source " << source->name() << ", model_sha256 " << source->model_sha256()
            << " -> " << a.out << "\n  totals:";
  for (const auto& [name, count] : totals) std::cout << " " << name << "x" << count;
  std::cout << "\n";
  // Timing goes to stderr only, never into the output folder (CONTRIBUTING: no wall clock in results).
  // The first frame pays the network's one-off allocations; the mean is over the others.
  const auto mean_after_first = [](const std::vector<double>& v) {
    double sum = 0;
    for (size_t i = v.size() > 1 ? 1 : 0; i < v.size(); ++i) sum += v[i];
    return sum / double(v.size() > 1 ? v.size() - 1 : v.size());
  };
  std::cerr << "time: first frame " << FormatFixed(wall_ms[0], 1) << " ms; then " << FormatFixed(mean_after_first(wall_ms), 1)
            << " ms/frame wall, " << FormatFixed(mean_after_first(cpu_ms), 1)
            << " ms/frame CPU (detection only, excl. image loading)\n";
  return kExitOk;
}

}  // namespace

void RegisterDetectCommand(CLI::App& root, CommandList& out) {
  auto args = std::make_shared<DetectArgs>();
  CLI::App* app = root.add_subcommand(
      "detect", "Precompute per-frame detections (boxes, classes, masks) into dynref's mask format");
  app->add_option("--source", args->source,
                  "nanodet | hog | onnx-yolo[:MODEL] | onnx-maskrcnn[:MODEL] | onnx-yolact[:MODEL] | files[:DIR] | labels[:DIR] | gt[:MODE]")
      ->required();
  app->add_option("--sequence", args->sequence, "TUM/Bonn/synthetic sequence folder");
  app->add_option("--image", args->image, "Single image instead of a sequence");
  app->add_option("--out", args->out, "Output dynref-detections folder");
  app->add_option("--camera", args->camera, "Camera preset or ORB-SLAM2 YAML (default: auto)");
  CLI::Option* frames = app->add_option("--frames", args->frames, "Frames A, A-B or A- (0-based, inclusive; default: all)");
  app->add_option("--input", args->input, "Folder for --source files / labels");
  app->add_option("--mode", args->mode, "Detections mode of a synthetic sequence for --source gt");
  app->add_option("--model", args->options.model_path, "Network ONNX (default: bundled models/nanodet.onnx)");
  app->add_option("--model-sha256", args->options.model_sha256, "Expected sha256 of --model");
  app->add_option("--mask-model", args->options.mask_model_path, "Selfie segmenter ONNX (default: bundled)");
  CLI::Option* conf = app->add_option("--conf", args->options.confidence_threshold,
                  "Confidence threshold in [0, 1] (default: nanodet 0.3, onnx-yolo 0.25, onnx-maskrcnn / onnx-yolact 0.05, hog 0.5)");
  app->add_option("--nms-iou", args->options.nms_iou, "Per-class NMS IoU threshold")->capture_default_str();
  app->add_option("--max-detections", args->options.max_detections, "Per frame")->capture_default_str();
  app->add_option("--input-size", args->options.yolo_input_size, "onnx-yolo / onnx-yolact square input size (the default 640 means 550 for onnx-yolact)")->capture_default_str();
  app->add_option("--class-names", args->options.class_names_file, "onnx-yolo: one class name per line");
  app->add_flag("--no-masks", args->no_masks, "Boxes only (skip selfie / YOLO-seg masks)");
  app->add_option("--temporal-gap", args->temporal.max_gap,
                  "Track persons across frames; carry a missed one this many frames as a box (0 = off; tracks.txt)")
      ->capture_default_str();
  app->add_option("--temporal-iou", args->temporal.iou_link, "Box IoU linking a detection to a track")
      ->capture_default_str();
  app->add_option("--overlay", args->overlay, "With --image: write the detections drawn on it (PNG)");
  app->add_option("--overlays", args->overlays, "With --sequence: write one overlay PNG per frame here");
  app->add_option("--repeat", args->repeat, "With --image: time N further runs (benchmark, stderr)")
      ->check(CLI::Range(0, 100000));
  out.push_back({app, [args, conf, frames] {
                   args->conf_given = conf->count() > 0;
                   args->frames_given = frames->count() > 0;
                   return RunDetect(*args);
                 }});
}

}  // namespace dynref::cli
