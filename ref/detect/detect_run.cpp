#include "detect/detect_run.h"

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <map>
#include <sstream>
#include <sys/stat.h>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/frame_range.h"
#include "core/version.h"
#include "detect/overlay.h"
#include "io/image_file.h"
#include "io/mask_format.h"
#include "io/sequence.h"

namespace dynref::detect {
namespace {

using DetectClock = std::chrono::steady_clock;

std::string DetectSpecOf(const DetectRunOptions& a) {
  std::string spec = a.source;
  if ((spec == "files" || spec == "labels") && !a.input.empty()) spec += ":" + a.input;
  if (spec == "gt" && !a.mode.empty()) spec += ":" + a.mode;
  return spec;
}

// Every option checked before anything is opened; InputError names the option.
void CheckDetectOptions(const DetectRunOptions& a) {
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
  CheckDetectionSpec(DetectSpecOf(a), o, "--source");
  try {
    a.temporal.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError("--temporal-gap/--temporal-iou", e.what());
  }
}

void WriteDetectPng(const std::string& path, const cv::Mat& image) {
  const std::string tmp = TempPathFor(path) + ".png";
  if (!dynref::ImageWrite(tmp, image)) throw InputError(path, "cannot write PNG");
  AtomicRename(tmp, path);
}

std::string DetectSummary(const FrameDetections& f) {
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

void PrintDetectInstances(const FrameDetections& f, std::ostream& out) {
  for (const auto& d : f.instances)
    out << "  " << d.id << " " << d.class_name << " conf " << FormatFixed(d.confidence, 3) << " box ["
        << FormatFixed(d.x_min, 1) << ", " << FormatFixed(d.y_min, 1) << ", " << FormatFixed(d.x_max, 1)
        << ", " << FormatFixed(d.y_max, 1) << "]" << (d.has_mask ? " mask" : "") << "\n";
}

std::string DetectInfoText(const DetectRunOptions& a, const DetectionSource& src, size_t first, size_t last) {
  const DetectSourceOptions& o = a.options;
  std::ostringstream s;
  s << "# parameters of the `dynref detect` run that wrote this folder (no timings)\n"
    << "dynref " << DYNREF_VERSION << " " << DYNREF_GIT_COMMIT << "\n"
    << "source_spec " << DetectSpecOf(a) << "\nsource " << src.name() << "\nmodel_sha256 " << src.model_sha256()
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

void DetectImage(const DetectRunOptions& a, std::ostream& out, std::ostream& timing) {
  auto source = MakeDetectionSource(DetectSpecOf(a), a.options);
  const cv::Mat bgr = dynref::ImageRead(a.image, cv::IMREAD_COLOR);
  if (bgr.empty()) throw InputError(a.image, "cannot read image");
  std::string stem = a.image.substr(a.image.find_last_of('/') + 1);
  stem = stem.substr(0, stem.find_last_of('.'));
  FrameDetections f = source->Detect(bgr, stem);  // first call pays one-off allocations
  // --repeat N: N more timed runs of the same frame (a benchmark; output must not change).
  const auto t0 = DetectClock::now();
  const std::clock_t c0 = std::clock();
  for (int r = 0; r < a.repeat; ++r) f = source->Detect(bgr, stem);
  out << a.image << " (" << bgr.cols << "x" << bgr.rows << "): " << DetectSummary(f) << "\n";
  PrintDetectInstances(f, out);
  if (a.repeat > 0)
    timing << "time: " << FormatFixed(std::chrono::duration<double, std::milli>(DetectClock::now() - t0).count() / a.repeat, 1)
           << " ms/frame wall, " << FormatFixed(1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / a.repeat, 1)
           << " ms/frame CPU over " << a.repeat << " repeats\n";
  if (!a.overlay.empty()) WriteDetectPng(a.overlay, DrawDetections(bgr, f));
  if (!a.out.empty()) {
    DetectionsWriter w(a.out, source->name(), source->model_sha256());
    w.Write(f);
    w.Finish();
  }
}

// One `dynref detect --sequence` run: the source, the staging folder, the tracks and the tallies.
struct SequenceDetectRun {
  const DetectRunOptions& a;
  const Sequence& seq;
  DetectionSource& source;
  DetectionsWriter writer;
  TemporalLinker linker;  // --temporal-gap N: a missed person is carried N frames (tracks.txt)
  std::ostringstream tracks;
  std::map<std::string, int> totals;
  std::vector<double> wall_ms, cpu_ms;  // per frame

  SequenceDetectRun(const DetectRunOptions& options, const Sequence& sequence, DetectionSource& src,
                    const std::string& out_dir)
      : a(options), seq(sequence), source(src), writer(out_dir, src.name(), src.model_sha256()),
        linker(options.temporal, cv::Size(sequence.camera.width, sequence.camera.height)) {
    tracks << "# rgb_stamp instance_id track origin (detected | carried), dynref detect --temporal-gap "
           << a.temporal.max_gap << "\n";
  }

  // Detect (+ temporal links), check the mask size, write, print one line, draw the overlay.
  void Frame(const FrameEntry& fe, std::ostream& out) {
    const bool need = source.needs_image() || !a.overlays.empty();
    const cv::Mat bgr = need ? LoadRgb(seq, fe) : cv::Mat();
    const auto t0 = DetectClock::now();
    const std::clock_t c0 = std::clock();
    FrameDetections f = source.Detect(bgr, fe.rgb_stamp_text);
    if (a.temporal.max_gap > 0) {
      std::vector<TrackLink> links;
      f = linker.Process(f, fe.rgb_stamp, &links);
      for (const TrackLink& l : links)
        tracks << fe.rgb_stamp_text << " " << l.instance_id << " " << l.track << " " << (l.carried ? "carried" : "detected")
               << "\n";
    }
    cpu_ms.push_back(1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC);
    wall_ms.push_back(std::chrono::duration<double, std::milli>(DetectClock::now() - t0).count());
    CheckMaskSize(fe, f);
    writer.Write(f);
    for (const auto& d : f.instances) ++totals[d.class_name];
    out << "frame " << fe.index << " " << fe.rgb_stamp_text << ": " << DetectSummary(f) << "\n";
    if (!a.overlays.empty()) WriteDetectPng(a.overlays + "/" + fe.rgb_stamp_text + ".png", DrawDetections(bgr, f));
  }

  // Sources that never decode the frame (files:, labels:) are checked against the camera size
  // here (issue 20 item 7: 320x240 masks of a 640x480 sequence were accepted).
  void CheckMaskSize(const FrameEntry& fe, const FrameDetections& f) const {
    if (!f.instance_ids.empty() && (f.instance_ids.cols != seq.camera.width || f.instance_ids.rows != seq.camera.height))
      throw InputError(a.source, "frame " + fe.rgb_stamp_text + ": mask is " + std::to_string(f.instance_ids.cols) + "x" +
                                     std::to_string(f.instance_ids.rows) + " but the sequence's camera is " +
                                     std::to_string(seq.camera.width) + "x" + std::to_string(seq.camera.height));
  }

  // The first frame pays the network's one-off allocations; the mean is over the others.
  void PrintTiming(std::ostream& timing) const {
    const auto mean_after_first = [](const std::vector<double>& v) {
      double sum = 0;
      for (size_t i = v.size() > 1 ? 1 : 0; i < v.size(); ++i) sum += v[i];
      return sum / double(v.size() > 1 ? v.size() - 1 : v.size());
    };
    timing << "time: first frame " << FormatFixed(wall_ms[0], 1) << " ms; then " << FormatFixed(mean_after_first(wall_ms), 1)
           << " ms/frame wall, " << FormatFixed(mean_after_first(cpu_ms), 1)
           << " ms/frame CPU (detection only, excl. image loading)\n";
  }
};

void DetectSequence(const DetectRunOptions& a, std::ostream& out, std::ostream& timing) {
  SequenceOptions so;
  so.camera = a.camera;
  const Sequence seq = OpenSequence(a.sequence, so);
  const FrameRange range = a.frames.empty() ? FrameRange{} : ParseFrameRange(a.frames);
  const size_t first = static_cast<size_t>(range.first);
  const size_t last = static_cast<size_t>(range.LastIn(static_cast<int64_t>(seq.frames.size())));
  auto source = MakeDetectionSource(DetectSpecOf(a), a.options);  // after the cheap argument checks
  if (!a.overlays.empty()) ::mkdir(a.overlays.c_str(), 0755);
  // The output folder is a unit (issue 20 item 6): written in a staging folder and renamed onto
  // --out when every frame is written, replacing an earlier detections folder whole (a failed
  // rerun used to leave the old index.txt beside the new format.txt).
  const std::string target = StagingDirectory::NormalisedTarget(a.out);
  if (!IsReplaceableDetections(target)) throw InputError("--out", a.out + " " + kNotDetections);
  StagingDirectory staging(target);
  const std::string out_dir = staging.dir();
  SequenceDetectRun run(a, seq, *source, out_dir);
  for (size_t i = first; i <= last; ++i) run.Frame(seq.frames[i], out);
  run.writer.Finish();
  AtomicWriteFile(out_dir + "/detect_info.txt", DetectInfoText(a, *source, first, last));
  if (a.temporal.max_gap > 0) AtomicWriteFile(out_dir + "/tracks.txt", run.tracks.str());
  PublishDirectory(out_dir, target, a.out, IsReplaceableDetections, kNotDetections);
  staging.Commit();
  out << "detect: " << last - first + 1 << " frames, source " << source->name() << ", model_sha256 "
      << source->model_sha256() << " -> " << a.out << "\n  totals:";
  for (const auto& [name, count] : run.totals) out << " " << name << "x" << count;
  out << "\n";
  run.PrintTiming(timing);
}

}  // namespace

void RunDetection(DetectRunOptions a, std::ostream& out, std::ostream& timing) {
  a.options.masks = !a.no_masks;
  a.options.sequence_root = a.sequence;
  if (a.image.empty() == a.sequence.empty()) throw InputError("<args>", "give exactly one of --sequence or --image");
  if (!a.sequence.empty() && a.out.empty()) throw InputError("<args>", "--sequence needs --out DIR");
  if (!a.overlay.empty() && a.image.empty()) throw InputError("<args>", "--overlay goes with --image (use --overlays DIR)");
  CheckDetectOptions(a);
  if (!a.image.empty())
    DetectImage(a, out, timing);
  else
    DetectSequence(a, out, timing);
}

}  // namespace dynref::detect
