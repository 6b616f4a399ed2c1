#include "reproduce/overview.h"

#include <filesystem>
#include <iostream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/version.h"
#include "render/canvas.h"
#include "render/overlay.h"
#include "trace/trace_reader.h"
#include "reproduce/arg_checks.h"
#include "reproduce/report_format.h"
#include "reproduce/report_plots.h"
#include "reproduce/workspace.h"
#include "io/image_file.h"

namespace fs = std::filesystem;

namespace dynref::reproduce {
namespace {

// Map files a run wrote (dense clouds, octrees, occupancy grids, the NeRF export), by name.
std::string MapFiles(const std::string& run_dir) {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(run_dir)) {
    if (!e.is_regular_file()) continue;
    const std::string ext = e.path().extension().string();
    const std::string rel = fs::relative(e.path(), run_dir).string();
    const bool map = ext == ".ply" || ext == ".pcd" || ext == ".ot" || ext == ".bt" || ext == ".pgm" ||
                     (ext == ".yaml" && rel.find("map") != std::string::npos) || rel == "nerf/transforms.json";
    if (map) files.push_back(rel + " (" + FormatFixed(e.file_size() / 1024.0, 0) + " KiB)");
  }
  std::sort(files.begin(), files.end());
  std::string text;
  for (const std::string& f : files) text += (text.empty() ? "" : ", ") + f;
  return text.empty() ? "-" : text;
}

std::string Modules(const RunSummary& s) {
  std::string text;
  for (const char* m : {"extraction", "tracking", "local_mapping", "stages"}) {
    auto it = s.ms_modules.find(m);
    if (it != s.ms_modules.end()) text += (text.empty() ? "" : ", ") + std::string(m) + " " + Num(it->second, 1);
  }
  return text.empty() ? "-" : text;
}

// The same frame's overlay of every run side by side (3 per row), each captioned with its method.
// A run traced at level frames (a method without stages, e.g. orb) has no per-feature records to
// draw: it is left out and named in the returned list.
std::vector<std::string> OverlayMontage(const std::vector<RunSummary>& runs, int64_t frame, const std::string& work,
                                        const std::string& png) {
  std::vector<render::Canvas> tiles;
  std::vector<std::string> skipped;
  for (const RunSummary& s : runs) {
    if (trace::TraceReader(render::ReadRunInfo(s.run_dir).trace_path).level() != trace::Level::kFull) {
      skipped.push_back(s.label);
      continue;
    }
    render::OverlayOptions o;
    o.gt = true;
    o.out_dir = work + "/overview_overlays/" + s.label;
    const std::vector<std::string> files = render::RenderRunOverlays(s.run_dir, frame, frame, o);
    if (files.empty()) continue;
    render::Canvas c = render::Canvas::FromBgr(dynref::ImageRead(files.front(), cv::IMREAD_COLOR));
    c.Label(8, 8, s.label, render::Rgb{255, 255, 255}, 2);
    tiles.push_back(std::move(c));
  }
  if (!tiles.empty()) render::Montage(tiles, 3).WritePng(png);
  return skipped;
}

}  // namespace

void OverviewArgs::Check() const {
  if (frames < 10) throw InputError("--frames", "must be >= 10, got " + std::to_string(frames));
  if (methods.empty()) throw InputError("--methods", "name at least one method");
  if (overlay_frame >= frames) throw InputError("--overlay-frame", "must be a frame of the sequence (< --frames)");
}

int RunOverview(const OverviewArgs& a) {
  a.Check();
  MakeReportFolders(a.out, a.work);
  SynthSpec spec;
  spec.frames = a.frames;
  spec.seed = a.seed;
  Workspace ws(SeedWorkDir(a.work, a.seed), spec, a.reuse);
  const std::string seq = ws.EnsureSequence(a.preset);
  std::vector<RunSummary> runs;
  for (const std::string& m : a.methods) {
    std::cerr << "overview: " << m << " (" << runs.size() + 1 << "/" << a.methods.size() << ")\n";
    runs.push_back(ws.Run(seq, m, LoadMethodConfig(MethodConfigPath(m)), m));
  }
  const fs::path dir = fs::path(a.out).parent_path();
  const std::string stem = fs::path(a.out).stem().string();
  LabelledRuns shown;
  for (const RunSummary& s : runs) shown.push_back({s.label, s.run_dir});
  PlotTrajectoriesTopView(seq, shown, "Trajectories seen from above: " + a.preset, (dir / (stem + "_trajectories.png")).string());
  PlotAteOverTime(seq, shown, "ATE over time: " + a.preset, (dir / (stem + "_ate.png")).string());
  const int64_t frame = a.overlay_frame >= 0 ? a.overlay_frame : a.frames / 2;
  const std::vector<std::string> no_overlay = OverlayMontage(runs, frame, a.work, (dir / (stem + "_overlays.png")).string());

  std::string md = "# dynref overview: every method on one sequence\n\n";
  md += "Made by `dynref overview --preset " + a.preset + " --frames " + std::to_string(a.frames) + " --seed " +
        std::to_string(a.seed) + "` at commit " + DYNREF_GIT_COMMIT + ": synthetic `" + a.preset +
        "` (yolo-like detections), every method's `configs/<method>.yaml`, evaluated against the sequence's ground truth.\n\n";
  if (!a.viewer.empty())
    md += "**Browse the runs:** [the run viewer](" + a.viewer + ") (frame slider, click a feature for its history).\n\n";
  md += "| method | end state | tracked | ATE RMSE (m) | RPE trans (m/s) | RPE rot (deg/s) | ms/frame (slam) | modules (ms/frame) | "
        "rejected features: precision / recall (%) | map files |\n|---|---|---|---|---|---|---|---|---|---|\n";
  int code = 0;
  for (const RunSummary& s : runs) {
    if (s.end_state != "complete") code = 1;
    const std::string pr = s.has_pr ? Pct(s.tp, s.tp + s.fp) + " / " + Pct(s.tp, s.tp + s.fn) : "-";
    md += "| " + s.label + " | " + s.end_state + " | " + std::to_string(s.tracked) + "/" + std::to_string(s.frames) +
          " | " + (s.has_ate ? Num(s.ate.rmse) : "- (" + s.ate_problem + ")") + " | " +
          (s.has_rpe ? Num(s.rpe_trans.rmse) : "-") + " | " + (s.has_rpe ? Num(s.rpe_rot.rmse, 3) : "-") + " | " +
          Num(s.ms_slam, 1) + " | " + Modules(s) + " | " + pr + " | " + MapFiles(s.run_dir) + " |\n";
  }
  md += "\nPrecision / recall: a feature a stage rejected is a true positive when its instance moves in the ground "
        "truth (`SEQ/gt/moving.txt`). ms/frame is thread CPU on this machine (run.json), one thread.\n\n";
  md += "## Trajectories\n\n![trajectories](" + stem + "_trajectories.png)\n\n![ATE over time](" + stem + "_ate.png)\n\n";
  md += "## Frame " + std::to_string(frame) + " in every method\n\nFeatures coloured by P(dynamic), crosses rejected, "
        "rings the ground truth (red moving, white static).";
  for (size_t i = 0; i < no_overlay.size(); ++i)
    md += std::string(i == 0 ? " Not shown (traced per frame only, no stages): " : ", ") + no_overlay[i] +
          (i + 1 == no_overlay.size() ? "." : "");
  md += "\n\n![overlays](" + stem + "_overlays.png)\n";
  AtomicWriteFile(a.out, md);
  std::cout << "overview: wrote " << a.out << "\n";
  return code;
}

}  // namespace dynref::reproduce
