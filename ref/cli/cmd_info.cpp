// `dynref info SEQ`: what dynref reads from a TUM/Bonn/synthetic sequence folder.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
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
#include "render/overlay.h"

namespace dynref::cli {
namespace {

struct InfoArgs {
  std::string root, camera, association;
  double max_diff = 0.02;
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

int RunInfo(const InfoArgs& a) {
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
              "ground-truth coverage, camera");
  app->add_option("SEQ", args->root, "Sequence folder (rgb.txt, depth.txt, groundtruth.txt)")
      ->required();
  app->add_option("--camera", args->camera,
                  "tum_fr1|tum_fr2|tum_fr3|bonn|synthetic or an ORB-SLAM2 YAML; default: "
                  "camera.yaml in the folder, else guessed from the folder name");
  app->add_option("--max-diff", args->max_diff, "RGB/depth association max difference in s")
      ->capture_default_str();
  app->add_option("--association", args->association,
                  "Use this associate.py output instead of associating rgb.txt/depth.txt");
  out.push_back({app, [args] { return RunInfo(*args); }});
}

}  // namespace dynref::cli
