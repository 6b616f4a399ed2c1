#include "reproduce/semantic_tables.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/version.h"
#include "io/ply.h"
#include "dynamic/semantic/components.h"
#include "eval/map_eval.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "render/overlay.h"
#include "reproduce/arg_checks.h"
#include "reproduce/paper_table.h"
#include "reproduce/report_format.h"
#include "reproduce/report_plots.h"
#include "reproduce/workspace.h"
#include "synth/world.h"

namespace fs = std::filesystem;

namespace dynref::reproduce {
namespace {

// The three maps compared: configs/<config>.yaml, the map file in its run folder.
struct MapVariant {
  std::string config, label, map_file;
};
const std::vector<MapVariant>& MapVariants() {
  static const std::vector<MapVariant> v = {
      {"semantic", "semantic (seed 002)", "semantic_map.ply"},
      {"semantic_orbmap", "same mapping, no removal", "semantic_map.ply"},
      {"sgdo", "SGDO-SLAM dense map", "dense_map.ply"},
  };
  return v;
}

// Map files of the semantic run, in pipeline order: (file suffix, what).
const std::vector<std::pair<std::string, std::string>>& StageFiles() {
  static const std::vector<std::pair<std::string, std::string>> f = {
      {"semantic_map_raw.pcd", "raw"}, {"semantic_map_sor.pcd", "SOR"},  {"semantic_map.pcd", "voxel"},
      {"semantic_map.ot", "octree .ot"}, {"semantic_map.bt", "octree .bt"}, {"semantic_map_grid.pgm", "grid .pgm"}};
  return f;
}

// Paper row (002-filesizes.csv "Sequence") of a preset; empty when the paper gives no size.
std::string SemanticPaperRow(const std::string& preset) {
  static const std::map<std::string, std::string> rows = {
      {"sitting_halfsphere", "fr3/s/half"}, {"sitting_static", "fr3/s/static"}, {"walking_halfsphere", "fr3/w/half"},
      {"walking_rpy", "fr3/w/rpy"},         {"walking_static", "fr3/w/static"}, {"static_rpy", "fr2/rpy"}};
  const auto it = rows.find(preset);
  return it == rows.end() ? std::string() : it->second;
}

double FileMB(const std::string& path) {
  std::error_code ec;
  const auto n = fs::file_size(path, ec);
  return ec ? std::nan("") : static_cast<double>(n) / 1e6;
}

struct NonPriorCounts {
  int64_t tp = 0, fp = 0, fn = 0, tn = 0;
};

// The interaction test replayed on every frame with semantic.mask's own code and options, each
// prior-static detection judged against the ground truth: truly non-prior dynamic iff the GT
// instance under most of its mask moves in that frame (SEQ/gt/moving.txt).
NonPriorCounts ReplayNonPrior(const std::string& seq_dir, const std::string& detections,
                              const semantic::MaskOptions& o) {
  NonPriorCounts c;
  const Sequence seq = OpenSequence(seq_dir);
  const DetectionsReader det_reader(seq_dir + "/detections/" + detections);
  const render::GroundTruthLabels gt(seq_dir);
  for (const FrameEntry& f : seq.frames) {
    if (!det_reader.Has(f.rgb_stamp_text) || !gt.Has(f.rgb_stamp_text)) continue;
    const FrameDetections det = det_reader.Read(f.rgb_stamp_text);
    const semantic::InstanceClasses cls = semantic::ClassifyInstances(det, LoadDepthMeters(seq, f), o);
    const cv::Mat gt_ids = gt.Read(f.rgb_stamp_text).instance_ids;
    const std::set<int> moving = gt.Moving(f.rgb_stamp_text);
    // One pass over the frame: detection instance -> GT instance -> pixels under its mask.
    std::map<int, std::map<int, int>> votes;
    if (!det.instance_ids.empty() && !gt_ids.empty())
      for (int y = 0; y < gt_ids.rows; ++y)
        for (int x = 0; x < gt_ids.cols; ++x) {
          const int d = det.instance_ids.at<uint16_t>(y, x);
          if (d != 0 && cls.prior_static.count(d)) ++votes[d][gt_ids.at<uint16_t>(y, x)];
        }
    for (int id : cls.prior_static) {
      int best = 0, best_n = 0;
      for (const auto& [g, n] : votes[id])
        if (g != 0 && n > best_n) best = g, best_n = n;
      const bool truth = best != 0 && moving.count(best) > 0;
      const bool said = cls.non_prior_dynamic.count(id) > 0;
      c.tp += truth && said, c.fp += !truth && said, c.fn += truth && !said, c.tn += !truth && !said;
    }
  }
  return c;
}

void SemanticCheckArgs(const SemanticTableArgs& a) {
  CheckMatrixArgs(a.frames, a.seeds, a.detections, a.sequences, a.reuse, a.collect);
  CheckReportPaths(a.out, a.work);
}

struct SemanticCell {  // one preset, over seeds
  std::map<std::string, std::vector<double>> mb;      // stage file -> MB per seed (semantic run)
  std::vector<MapEvalResult> quality[3];               // per map variant, per seed
  NonPriorCounts non_prior;
  std::vector<RunSummary> runs;
};

}  // namespace

namespace {

// The shared workspace of one semantic-filesizes call: the paper's sizes, the configs and the cells.
struct SemanticRun {
  const SemanticTableArgs& a;
  PaperTable paper;
  std::vector<MethodConfig> configs;  // MapVariants() in order
  semantic::MaskOptions mask_options;
  std::map<std::string, SemanticCell> cells;
  explicit SemanticRun(const SemanticTableArgs& args) : a(args) {}
};

// One preset of one seed: every map variant run, its files measured and its map evaluated, then
// the non-prior decisions replayed.
void RunPreset(SemanticRun& t, Workspace& ws, const std::string& preset) {
  const SemanticTableArgs& a = t.a;
  const auto& configs = t.configs;
  const std::string seq = ws.EnsureSequence(preset);
  SemanticCell& c = t.cells[preset];
  const TumTrajectory gt = ReadTumTrajectory(seq + "/groundtruth.txt");
  const dense::TriangleMesh mesh = ReadPlyMesh(seq + "/gt/static_scene.ply");
  const MeshDistance to_static(mesh, MapEvalOptions{}.sample_m);  // one index for the three maps
  const dense::PointCloud observed = ReadPly(seq + "/gt/static_observed.ply");
  const dense::PointCloud movers = ReadPly(seq + "/gt/movers_observed.ply");
  for (size_t v = 0; v < MapVariants().size(); ++v) {
    const RunSummary s = ws.Run(seq, preset + "/" + MapVariants()[v].config, configs[v], MapVariants()[v].label);
    c.runs.push_back(s);
    if (v == 0)
      for (const auto& [file, what] : StageFiles()) c.mb[file].push_back(FileMB(s.run_dir + "/" + file));
    const dense::PointCloud cloud = ReadPly(s.run_dir + "/" + MapVariants()[v].map_file);
    const SE3 T = MapToGroundTruth(gt, ReadTumTrajectory(s.run_dir + "/trajectory.txt"), MapAlign::kFirstCamera);
    std::vector<Eigen::Vector3d> map;
    map.reserve(cloud.size());
    for (const auto& p : cloud) map.push_back(T * Eigen::Vector3d(p.x, p.y, p.z));
    std::cerr << "reproduce: map-eval " << preset << "/" << MapVariants()[v].config << "\n";
    c.quality[v].push_back(EvaluateMap(map, to_static, observed, movers, MapEvalOptions{}));
  }
  const NonPriorCounts n = ReplayNonPrior(seq, a.detections, t.mask_options);
  c.non_prior.tp += n.tp, c.non_prior.fp += n.fp, c.non_prior.fn += n.fn, c.non_prior.tn += n.tn;
}

void SemanticWriteIntro(SemanticRun& t, std::ostringstream& md) {
  const SemanticTableArgs& a = t.a;
  const auto& cells = t.cells;
  std::vector<RunSummary> all;
  for (const auto& [preset, c] : cells) all.insert(all.end(), c.runs.begin(), c.runs.end());
  std::string cmd = "dynref reproduce semantic-filesizes --frames " + std::to_string(a.frames) + " --seeds " +
                    SeedListText(a.seeds) + " --detections " + a.detections;
  if (a.sequences != SemanticTableArgs{}.sequences) {
    cmd += " --sequences ";
    for (size_t i = 0; i < a.sequences.size(); ++i) cmd += (i ? "," : "") + a.sequences[i];
  }
  md << "# Semantic mapping (seed 002): map files per stage and map quality, on synthetic sequences\n\n"
     << "Written by `" << cmd << "` (dynref " << DYNREF_VERSION << ", commit " << DYNREF_GIT_COMMIT
     << "). Do not edit by hand.\n\n"
     << "- Runs made by dynref commit " << RunCommits(all) << ".\n"
     << "- Sequences: `dynref synth --preset P --frames " << a.frames << " --seed S --detections " << a.detections
     << "` for seeds S = " << SeedListText(a.seeds) << "; the paper mapped the full real sequences (frame counts "
     << "below) and a D455 in two rooms, one run each.\n"
     << "- Maps: `configs/semantic.yaml` (the method), `configs/semantic_orbmap.yaml` (the same mapping on the plain "
     << "backbone, nothing removed: where ghosts come from), `configs/sgdo.yaml` (SGDO-SLAM's dense map, seed 001).\n"
     << "- Cells: mean ± population S.D. over seeds. Paper values: `reports/paper-tables/002-filesizes.csv` "
     << "(Sec. 4.4 text; only the voxel step is quantified there).\n\n"
     << FramesTable(a.sequences, a.frames, [&] {
          std::vector<std::string> rows;
          for (const std::string& p : a.sequences) rows.push_back(p == "static_rpy" ? "" : SemanticPaperRow(p));  // fr2: other length
          return rows;
        }());
}

void WriteFileSizes(SemanticRun& t, std::ostringstream& md) {
  const SemanticTableArgs& a = t.a;
  auto& cells = t.cells;
  const PaperTable& paper = t.paper;
  md << "\n## Map files per stage, MB (semantic run)\n\n| Sequence |";
  for (const auto& [file, what] : StageFiles()) md << " " << what << " |";
  md << " voxel / raw % | SOR removed % | .ot / raw % | paper before voxel | paper after voxel | paper ratio % |\n|---|";
  for (size_t i = 0; i < StageFiles().size() + 6; ++i) md << "---|";
  md << "\n";
  for (const std::string& preset : a.sequences) {
    const SemanticCell& c = cells[preset];
    md << "| " << preset << " |";
    for (const auto& [file, what] : StageFiles()) md << " " << MeanSd(c.mb.at(file), file.find("grid") != std::string::npos ? 3 : 2) << " |";
    std::vector<double> ratio, sor, ot;
    for (size_t k = 0; k < a.seeds.size(); ++k) {
      const double raw = c.mb.at("semantic_map_raw.pcd")[k];
      ratio.push_back(100.0 * c.mb.at("semantic_map.pcd")[k] / raw);
      sor.push_back(100.0 * (1.0 - c.mb.at("semantic_map_sor.pcd")[k] / raw));
      ot.push_back(100.0 * c.mb.at("semantic_map.ot")[k] / raw);
    }
    // 002-filesizes.csv rows start with the dataset ("TUM"): the sequence is the second cell.
    const std::string row = SemanticPaperRow(preset);
    const auto cell = [&](size_t column) {
      for (const auto& r : paper.ordered)
        if (!row.empty() && r.size() > column && r[1] == row) return std::strtod(r[column].c_str(), nullptr);
      return std::nan("");
    };
    md << " " << MeanSd(ratio, 1) << " | " << MeanSd(sor, 2) << " | " << MeanSd(ot, 1) << " | " << Num(cell(2), 1)
       << " | " << Num(cell(3), 1) << " | " << Num(cell(4), 1) << " |\n";
  }
  md << "\nPCD files are binary with x y z rgb (16 bytes per point), so MB follow the point counts. The paper: "
        "SOR removed ~1.24 % of the points, the octree file is 16.5-35 % of the dense map, voxel output 18-54.6 % "
        "of its input.\n";
}

void WriteMapQuality(SemanticRun& t, std::ostringstream& md) {
  const SemanticTableArgs& a = t.a;
  auto& cells = t.cells;
  md << "\n## Map quality against the synthetic scene truth (`dynref map-eval`)\n\n"
     << "Accuracy: distance of each map point to the static scene mesh (median / 95th percentile, m); completeness: "
        "observed static 2 cm voxels with a map point within 5 cm; ghosts: map points within 5 cm of a mover's "
        "observed surface at any time and farther than 5 cm from static geometry. Maps anchored by the run's first "
        "camera.\n\n| Sequence | map | points | accuracy median | accuracy p95 | completeness % | ghosts % |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const std::string& preset : a.sequences)
    for (size_t v = 0; v < MapVariants().size(); ++v) {
      std::vector<double> pts, med, p95, comp, ghost;
      for (const MapEvalResult& r : cells[preset].quality[v]) {
        pts.push_back(static_cast<double>(r.map_points));
        med.push_back(r.accuracy.median), p95.push_back(r.accuracy_p95);
        comp.push_back(100.0 * r.completeness), ghost.push_back(100.0 * r.ghost_fraction);
      }
      md << "| " << preset << " | " << MapVariants()[v].label << " | " << MeanSd(pts, 0) << " | " << MeanSd(med) << " | "
         << MeanSd(p95) << " | " << MeanSd(comp, 1) << " | " << MeanSd(ghost, 2) << " |\n";
    }
}

void WriteNonPrior(SemanticRun& t, std::ostringstream& md) {
  const SemanticTableArgs& a = t.a;
  auto& cells = t.cells;
  md << "\n## Non-prior dynamic objects (interaction test) against ground truth\n\n"
     << "Every prior-static detection of every frame (summed over seeds), replayed with `semantic.mask`'s own "
        "code and `configs/semantic.yaml`: truly non-prior dynamic iff the ground-truth instance under most of its "
        "mask moves in that frame (`SEQ/gt/moving.txt`: pushed or rolled chairs, a carried box).\n\n"
     << "| Sequence | detections | truly moving | said non-prior dynamic | precision % | recall % |\n|---|---|---|---|---|---|\n";
  for (const std::string& preset : a.sequences) {
    const NonPriorCounts& n = cells[preset].non_prior;
    md << "| " << preset << " | " << (n.tp + n.fp + n.fn + n.tn) << " | " << (n.tp + n.fn) << " | " << (n.tp + n.fp)
       << " | " << Pct(n.tp, n.tp + n.fp) << " | " << Pct(n.tp, n.tp + n.fn) << " |\n";
  }
}

// Ghost bars: semantic vs no removal vs sgdo.
void PlotGhosts(SemanticRun& t, std::ostringstream& md) {
  const SemanticTableArgs& a = t.a;
  auto& cells = t.cells;
  const fs::path report_dir = fs::path(a.out).parent_path();
  std::vector<render::BarSeries> series;
  for (size_t v = 0; v < MapVariants().size(); ++v) {
    render::BarSeries s{MapVariants()[v].label, {}, {}, render::SeriesColour(v + 4)};
    for (const std::string& preset : a.sequences) {
      std::vector<double> g;
      for (const MapEvalResult& r : cells[preset].quality[v]) g.push_back(100.0 * r.ghost_fraction);
      s.value.push_back(Mean(g));
      s.error.push_back(g.size() > 1 ? ComputeErrorStats(g).std : std::nan(""));
    }
    series.push_back(s);
  }
  render::BarChartOptions bo;
  bo.width = 1300;
  bo.title = "Ghost points, % of the map (mean +- S.D. over seeds " + SeedListText(a.seeds) + ")";
  bo.y_label = "ghosts [%]";
  const std::string png = (report_dir / (fs::path(a.out).stem().string() + "_ghosts.png")).string();
  PlotBars(a.sequences, series, bo, png);
  md << "\n## Plot\n\n![ghost fraction](" << fs::path(png).filename().string() << ")\n";
}

}  // namespace

int RunSemanticTable(const SemanticTableArgs& a) {
  SemanticCheckArgs(a);
  SemanticRun t(a);
  t.paper = ReadPaperTable(PaperTableDir() + "/002-filesizes.csv");
  const fs::path report_dir = fs::path(a.out).parent_path();
  if (!report_dir.empty()) fs::create_directories(report_dir);
  if (!a.collect) fs::create_directories(a.work);
  for (const MapVariant& v : MapVariants()) t.configs.push_back(LoadMethodConfig(MethodConfigPath(v.config)));
  t.mask_options = [&] {
    for (const StageConfig& sc : t.configs[0].stages)
      if (sc.name == "semantic.mask") return semantic::MaskOptionsFromParams(sc.params);
    throw InputError(t.configs[0].path, "configs/semantic.yaml has no semantic.mask stage");
  }();
  for (uint64_t seed : a.seeds) {
    Workspace ws(SeedWorkDir(a.work, seed), {a.frames, seed, a.detections}, a.reuse,
                 a.collect ? WorkMode::kCollect : WorkMode::kMake);
    ws.set_stage_trace_level("frames");  // sizes and maps only; full traces of 3 maps are GBs
    for (const std::string& preset : a.sequences) RunPreset(t, ws, preset);
  }
  std::ostringstream md;
  SemanticWriteIntro(t, md);
  WriteFileSizes(t, md);
  WriteMapQuality(t, md);
  WriteNonPrior(t, md);
  md << PaperNotes("002-filesizes.csv", t.paper.notes);
  PlotGhosts(t, md);
  AtomicWriteFile(a.out, md.str());
  std::cout << "reproduce: wrote " << a.out << "\n";
  return kExitOk;
}

void RegisterSemanticTables(TableRegistry& registry) {
  registry.Add(
      {"semantic-filesizes", "002 semantic mapping",
       "map files per stage vs the paper's sizes, map accuracy/completeness/ghosts, non-prior P/R",
       "Seed 002: map files per stage (raw, SOR, voxel, octree, grid) beside the paper's sizes, map accuracy/"
       "completeness/ghosts of semantic vs no removal vs sgdo, non-prior dynamic P/R, over seeds",
       [](CLI::App& app) {
         auto m = std::make_shared<SemanticTableArgs>();
         MatrixHelp help;
         help.work = "Working folder <work>/seed<S>/{seq,runs}";
         help.detections = "Synthetic detection mode (default yolo-like)";
         help.sequences = "Presets (default the paper's TUM analogues + walking_xyz + moving_box)";
         AddMatrixOptions(app, *m, help);
         AddReuseCollect(app, *m, "Reuse sequences/runs of an earlier call with identical inputs",
                         "Only read: sequences and runs already in --work");
         return TableCommand{m, [m] { return RunSemanticTable(*m); }};
       }});
}

}  // namespace dynref::reproduce
