// `dynref info SEQ`: what dynref reads from a TUM/Bonn/synthetic sequence folder.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/command.h"
#include "core/error.h"
#include "core/format.h"
#include "io/association.h"
#include "io/sequence.h"
#include "eval/statistics.h"
#include "detect/box_eval.h"
#include "detect/score_calibration.h"
#include "render/overlay.h"

namespace dynref::cli {
namespace {

struct InfoArgs {
  std::string root, camera, association, boxes;
  double max_diff = 0.02, iou = 0.5;
};

// Shortest text that reads back to v (517.3, not 517.29999999999995).
std::string Num(double v) {
  for (int precision = 15; precision < 17; ++precision) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) return buf;
  }
  return FormatDouble17(v);
}

// `dynref info DETECTIONS_DIR [--boxes HAND_BOXES]` (issue 39): the score distribution per class,
// the source's calibration to the papers' detectors, and recall / precision against hand boxes.
int RunDetectionsInfo(const InfoArgs& a) {
  const DetectionsReader reader(a.root);
  std::map<std::string, FrameDetections> frames;
  for (const std::string& stamp : reader.Stamps()) frames[stamp] = reader.Read(stamp);
  const std::vector<double> cuts = {0.25, 0.3, 0.4, 0.5};
  std::ostringstream o;
  o << "detections     " << a.root << "\n"
    << "source         " << reader.source() << " (model_sha256 " << reader.model_sha256() << ")\n"
    << "frames         " << frames.size() << "\n";
  const detect::ScoreCalibration& cal = detect::CalibrationForSource(reader.source());
  o << "calibration    " << cal.name << ": paper threshold 0.25 -> " << FormatFixed(cal.EquivalentThreshold(0.25), 3)
    << ", 0.5 -> " << FormatFixed(cal.EquivalentThreshold(0.5), 3) << " (" << cal.basis << ")\n";
  o << "scores per class: count  min  q25  median  q75  max  | >=0.25 >=0.3 >=0.4 >=0.5\n";
  for (const auto& [name, s] : detect::SummariseScores(frames, cuts)) {
    o << "  " << name << "  " << s.count << "  " << FormatFixed(s.min, 3) << "  " << FormatFixed(s.q25, 3) << "  "
      << FormatFixed(s.median, 3) << "  " << FormatFixed(s.q75, 3) << "  " << FormatFixed(s.max, 3) << "  |";
    for (int n : s.at_least) o << " " << n;
    o << "\n";
  }
  if (!a.boxes.empty()) {
    const std::vector<detect::HandBox> truth = detect::ReadHandBoxes(a.boxes);
    std::set<std::string> classes;
    for (const detect::HandBox& b : truth) classes.insert(b.class_name);
    for (const std::string& c : classes) {
      o << "vs " << a.boxes << " (" << c << ", IoU >= " << Num(a.iou) << "):\n";
      for (double t : {0.0, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5}) {
        const detect::MatchCounts m = detect::MatchAgainstHandBoxes(frames, truth, c, t, a.iou);
        o << "  conf >= " << FormatFixed(t, 2) << "  recall " << m.matched << "/" << m.truth << " = "
          << FormatFixed(m.Recall(), 3) << "  precision " << m.matched << "/" << m.detections << " = "
          << FormatFixed(m.Precision(), 3) << "\n";
      }
    }
  }
  std::cout << o.str();
  return kExitOk;
}

int RunInfo(const InfoArgs& a) {
  if (std::filesystem::is_regular_file(a.root + "/format.txt")) return RunDetectionsInfo(a);
  if (!a.boxes.empty()) throw InputError(a.boxes, "--boxes needs a detections folder as the argument");
  SequenceOptions opt;
  opt.camera = a.camera;
  opt.max_difference_s = a.max_diff;
  opt.association_file = a.association;
  const Sequence seq = OpenSequence(a.root, opt);
  const Camera& c = seq.camera;
  std::ostringstream o;
  o << "sequence       " << seq.root << "\n"
    << "frames         rgb.txt " << seq.rgb_count << ", depth.txt " << seq.depth_count << "\n"
    << "associated     " << seq.frames.size() << " RGB-D pairs (" << seq.association_source
    << ")\n";
  const double t0 = seq.frames.front().rgb_stamp, t1 = seq.frames.back().rgb_stamp;
  o << "time span      " << seq.frames.front().rgb_stamp_text << " .. "
    << seq.frames.back().rgb_stamp_text << " (" << FormatFixed(t1 - t0, 3) << " s)\n";
  if (seq.groundtruth.empty()) {
    o << "ground truth   none (no groundtruth.txt)\n";
  } else {
    std::vector<double> frame_stamps, gt_stamps;
    for (const auto& f : seq.frames) frame_stamps.push_back(f.rgb_stamp);
    for (const auto& p : seq.groundtruth) gt_stamps.push_back(p.stamp);
    const size_t covered = AssociateTum(frame_stamps, gt_stamps, a.max_diff).size();
    o << "ground truth   " << seq.groundtruth.size() << " poses, "
      << FormatFixed(gt_stamps.front(), 4) << " .. " << FormatFixed(gt_stamps.back(), 4);
    if (seq.groundtruth_duplicates_dropped)
      o << " (" << seq.groundtruth_duplicates_dropped << " duplicate stamp(s), later line kept)";
    o << "\nGT coverage    " << covered << " of " << seq.frames.size()
      << " frames have a ground-truth pose within " << FormatDouble17(a.max_diff)
      << " s (one-to-one, as associate.py)\n";
  }
  o << "camera         " << c.name << " [" << seq.camera_source << "]\n"
    << "  size " << c.width << "x" << c.height << "  fx " << Num(c.fx) << "  fy "
    << Num(c.fy) << "  cx " << Num(c.cx) << "  cy " << Num(c.cy)
    << "\n  distortion k1 k2 p1 p2 k3 = " << Num(c.k1) << " " << Num(c.k2)
    << " " << Num(c.p1) << " " << Num(c.p2) << " " << Num(c.k3)
    << "\n  depth factor " << Num(c.depth_factor) << " units/m  bf "
    << Num(c.bf) << "  ThDepth " << Num(c.th_depth) << "\n";
  // Synthetic ground-truth motion labels (SEQ/gt): how much of each frame moves.
  if (std::filesystem::is_directory(seq.root + "/gt")) {
    render::GroundTruthLabels gt(seq.root);
    std::vector<double> share;
    size_t with_motion = 0;
    for (const auto& f : seq.frames) {
      if (!gt.Has(f.rgb_stamp_text)) continue;
      const cv::Mat ids = gt.Read(f.rgb_stamp_text).instance_ids;
      const std::set<int> moving = gt.Moving(f.rgb_stamp_text);
      if (ids.empty()) continue;
      size_t n = 0;
      for (int y = 0; y < ids.rows; ++y)
        for (int x = 0; x < ids.cols; ++x) n += moving.count(ids.at<uint16_t>(y, x)) > 0;
      share.push_back(100.0 * static_cast<double>(n) / static_cast<double>(ids.total()));
      with_motion += n > 0;
    }
    if (!share.empty()) {
      const ErrorStats st = ComputeErrorStats(share);
      o << "moving pixels  " << FormatFixed(st.mean, 1) << " % mean, " << FormatFixed(st.median, 1) << " % median, "
        << FormatFixed(st.max, 1) << " % max per frame; " << with_motion << " of " << share.size()
        << " labelled frames show motion (SEQ/gt, moving.txt)\n";
    }
  }
  std::cout << o.str();
  return kExitOk;
}

}  // namespace

void RegisterInfoCommand(CLI::App& root, CommandList& out) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* app = root.add_subcommand(
      "info", "Describe a TUM/Bonn/dynref sequence folder: frames, associated pairs, time span, "
              "ground-truth coverage, camera; or a detections folder: scores per class, calibration, "
              "recall / precision against hand boxes");
  app->add_option("SEQ", args->root, "Sequence folder (rgb.txt, depth.txt, groundtruth.txt)")
      ->required();
  app->add_option("--camera", args->camera,
                  "tum_fr1|tum_fr2|tum_fr3|bonn|synthetic or an ORB-SLAM2 YAML; default: "
                  "camera.yaml in the folder, else guessed from the folder name");
  app->add_option("--max-diff", args->max_diff, "RGB/depth association max difference in s")
      ->capture_default_str();
  app->add_option("--association", args->association,
                  "Use this associate.py output instead of associating rgb.txt/depth.txt");
  app->add_option("--boxes", args->boxes,
                  "With a detections folder: hand boxes (rgb_stamp class label x0 y0 x1 y1) to score against");
  app->add_option("--iou", args->iou, "With --boxes: IoU for a match")->capture_default_str()->check(CLI::Range(0.0, 1.0));
  out.push_back({app, [args] { return RunInfo(*args); }});
}

}  // namespace dynref::cli
