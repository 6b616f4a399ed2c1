#include "reproduce/mgd_tables.h"

#include <map>
#include <sstream>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "core/version.h"
#include "reproduce/arg_checks.h"
#include "reproduce/paper_table.h"
#include "reproduce/report_format.h"
#include "reproduce/report_plots.h"
#include "reproduce/workspace.h"

namespace dynref::reproduce {
namespace {

struct MgdVariant {
  std::string config, label;
  std::string paper2, paper4;  // column in 000-table2 / 000-table4 and 5 ("" none)
};

// Columns of the ATE tables (trace level frames: clean CPU times).
const std::vector<MgdVariant>& MainVariants() {
  static const std::vector<MgdVariant> v = {
      {"orb", "ORB-SLAM2 backbone (orb)", "ORB-SLAM3", "ORB-SLAM3"},
      {"mgd_nd", "MGD-SLAM-nD (mgd-nd)", "", "MGD-SLAM-nD"},
      {"mgd", "MGD-SLAM (mgd)", "MGD-SLAM", "MGD-SLAM"},
  };
  return v;
}

// The cue ablations, traced at level full for precision / recall (traces dropped once counted).
const std::vector<MgdVariant>& CueVariants() {
  static const std::vector<MgdVariant> v = {
      {"mgd", "all cues + diffusion", "", ""},   {"mgd_LS", "only P_LS", "", ""},
      {"mgd_pro", "only P_pro", "", ""},         {"mgd_mf", "only P_mf", "", ""},
      {"mgd_nodiff", "no diffusion", "", ""},
  };
  return v;
}

// Paper row (000-table2/4/5) of a preset; "" when none.
std::string MgdPaperRow(const std::string& preset) {
  static const std::map<std::string, std::string> rows = {
      {"walking_xyz", "w_xyz"},   {"walking_static", "w_static"},   {"walking_rpy", "w_rpy"},
      {"walking_halfsphere", "w_half"}, {"sitting_xyz", "s_xyz"},   {"sitting_static", "s_static"},
      {"sitting_rpy", "s_rpy"},   {"sitting_halfsphere", "s_half"}};
  const auto it = rows.find(preset);
  return it == rows.end() ? std::string() : it->second;
}

struct MgdCell {
  std::vector<double> ate, rpe;  // seeds with a value
  int tracked = 0, frames = 0;
  std::map<std::string, std::vector<double>> ms;  // module -> per seed
  RunSummary pr;                                   // precision/recall counts summed over seeds
};

void MgdAddRun(const RunSummary& s, MgdCell& c) {
  c.tracked += s.tracked;
  c.frames += s.frames;
  if (s.has_ate) c.ate.push_back(s.ate.rmse);
  if (s.has_rpe) c.rpe.push_back(s.rpe_trans.rmse);
  for (const auto& [module, ms] : s.ms_modules) c.ms[module].push_back(ms);
  if (s.has_pr) AddRejectionCounts(c.pr, s);
}

double F1(int64_t tp, int64_t fp, int64_t fn) { return tp > 0 ? 2.0 * tp / (2.0 * tp + fp + fn) : 0.0; }
// "precision | recall | F1" in percent.
std::string Prf(int64_t tp, int64_t fp, int64_t fn) {
  return Pct(tp, tp + fp) + " | " + Pct(tp, tp + fn) + " | " + (tp + fp + fn > 0 ? Num(100.0 * F1(tp, fp, fn), 1) : "-");
}

void MgdCheckArgs(const MgdTableArgs& a) {
  if (a.table != "table2" && a.table != "table4") throw InputError("table", "unknown table '" + a.table + "'");
  CheckMatrixArgs(a.frames, a.seeds, a.detections, a.sequences, a.reuse, a.collect);
  CheckReportPaths(a.out, a.work);
}

using MgdGrid = std::map<std::string, std::vector<MgdCell>>;  // preset -> variants in order

}  // namespace

std::vector<std::string> MgdTableDefaultSequences(const std::string& table) {
  if (table == "table4") return {"walking_halfsphere", "walking_rpy", "walking_static", "walking_xyz"};
  return {"sitting_halfsphere", "sitting_rpy", "sitting_static", "sitting_xyz",
          "walking_halfsphere", "walking_rpy", "walking_static", "walking_xyz"};
}

namespace {

// Paper columns printed beside ours (Tables 4 and 5 also have MWSLAM, which dynref does not run).
const std::vector<std::string> kPaperCols2 = {"ORB-SLAM3", "MGD-SLAM"};
const std::vector<std::string> kPaperCols4 = {"ORB-SLAM3", "MWSLAM", "MGD-SLAM-nD", "MGD-SLAM"};

// The shared workspace of one MGD table: paper tables, variants, configs and every run.
struct MgdRun {
  const MgdTableArgs& a;
  PaperTable p2, p4, p5, p6;
  bool ablations = false;  // table2 without --no-ablations: the cue variants at trace level full
  const std::vector<MgdVariant>& main = MainVariants();
  const std::vector<MgdVariant>& cues = CueVariants();
  std::vector<MethodConfig> main_cfg, cue_cfg;
  MgdGrid grid, cue_grid;
  std::vector<RunSummary> all_runs;
  explicit MgdRun(const MgdTableArgs& args) : a(args) {}
};

// Runs: the main variants at trace level frames, the cue ablations at level full, seed by seed.
void RunMgdMatrix(MgdRun& t) {
  const MgdTableArgs& a = t.a;
  const auto &main = t.main, &cues = t.cues;
  const auto &main_cfg = t.main_cfg, &cue_cfg = t.cue_cfg;
  auto &grid = t.grid, &cue_grid = t.cue_grid;
  auto& all_runs = t.all_runs;
  const bool ablations = t.ablations;
  for (const std::string& p : a.sequences) grid[p].resize(main.size()), cue_grid[p].resize(cues.size());
  for (uint64_t seed : a.seeds) {
    Workspace ws(SeedWorkDir(a.work, seed), {a.frames, seed, a.detections}, a.reuse,
                 a.collect ? WorkMode::kCollect : WorkMode::kMake);
    for (const std::string& preset : a.sequences) {
      const std::string seq = ws.EnsureSequence(preset);
      ws.set_stage_trace_level("frames");
      for (size_t v = 0; v < main.size(); ++v) {
        all_runs.push_back(ws.Run(seq, preset + "/" + main[v].config, main_cfg[v], main[v].label));
        MgdAddRun(all_runs.back(), grid[preset][v]);
      }
      if (!ablations) continue;
      ws.set_stage_trace_level("full");
      ws.set_keep_full_traces(false);
      for (size_t v = 0; v < cues.size(); ++v) {
        all_runs.push_back(ws.Run(seq, preset + "/" + cues[v].config + "_full", cue_cfg[v], cues[v].label));
        MgdAddRun(all_runs.back(), cue_grid[preset][v]);
      }
    }
  }
}

void MgdWriteIntro(const MgdRun& t, std::ostringstream& md) {
  const MgdTableArgs& a = t.a;
  const auto& all_runs = t.all_runs;
  const std::string cmd = "dynref reproduce mgd-" + a.table + " --frames " + std::to_string(a.frames) + " --seeds " +
                          SeedListText(a.seeds) + " --detections " + a.detections + (a.no_ablations ? " --no-ablations" : "");
  md << "# MGD-SLAM (seed 000) " << (a.table == "table2" ? "Table 2" : "Tables 4-6") << " on synthetic sequences\n\n"
     << "Written by `" << cmd << "` (dynref " << DYNREF_VERSION << ", commit " << DYNREF_GIT_COMMIT
     << "). Do not edit by hand.\n\n"
     << "- Runs made by dynref commit " << RunCommits(all_runs) << ".\n"
     << "- Sequences: `dynref synth --preset P --frames " << a.frames << " --seed S --detections " << a.detections
     << "` for seeds S = " << SeedListText(a.seeds)
     << " (synthetic analogues of the TUM fr3 sequences; the paper uses the real ones). MGD-SLAM uses the boxes "
     << "only (Sec. 3.3), never the masks.\n"
     << "- Methods: `configs/<name>.yaml` (every parameter with its source); `orb` is dynref's ORB-SLAM2 backbone, "
     << "the paper's baseline column is ORB-SLAM3.\n"
     << "- ATE RMSE in metres after SE(3) alignment (TUM evaluate_ate.py) over the tracked frames: mean ± S.D. "
     << "over the " << a.seeds.size() << " seeds; 'tracked' = tracked frames of all runs of the row. "
     << "Paper values: `reports/paper-tables/000-table*.csv`, real data.\n\n"
     << FramesTable(a.sequences, a.frames, [&] {
          std::vector<std::string> rows;
          for (const std::string& p : a.sequences) rows.push_back(MgdPaperRow(p));
          return rows;
        }())
     << "\n";
}

// ATE (Table 2 / Table 4) or RPE (Table 5) of the main variants with the paper's columns.
void WriteValueTable(MgdRun& t, std::ostringstream& md, bool rpe, const PaperTable& paper,
                     const std::vector<std::string>& paper_cols) {
  const MgdTableArgs& a = t.a;
  const auto& main = t.main;
  auto& grid = t.grid;
  md << "| Sequence |";
  for (const MgdVariant& v : main) md << " " << v.label << " |";
  for (const std::string& c : paper_cols) md << " paper " << c << " |";
  md << " mgd-nd / mgd | tracked (orb / mgd-nd / mgd) |\n|---|";
  for (size_t i = 0; i < main.size() + paper_cols.size() + 2; ++i) md << "---|";
  md << "\n";
  for (const std::string& preset : a.sequences) {
    const std::vector<MgdCell>& cs = grid[preset];
    md << "| " << preset << (MgdPaperRow(preset).empty() ? "" : " (" + MgdPaperRow(preset) + ")") << " |";
    for (const MgdCell& c : cs) md << " " << MeanSd(rpe ? c.rpe : c.ate) << " |";
    for (const std::string& col : paper_cols) md << " " << Num(paper.Cell(MgdPaperRow(preset), col), 3) << " |";
    md << " " << Num(Mean(rpe ? cs[1].rpe : cs[1].ate) / Mean(rpe ? cs[2].rpe : cs[2].ate), 1) << "x |";
    for (size_t v = 0; v < cs.size(); ++v)
      md << (v ? " / " : " ") << Pct(cs[v].tracked, cs[v].frames) << " %";
    md << " |\n";
  }
}

// Table 2's cue ablations: dynamic point / line precision, recall, F1 against the truth.
void WriteCueAblations(MgdRun& t, std::ostringstream& md) {
  const MgdTableArgs& a = t.a;
  const auto& cues = t.cues;
  auto& cue_grid = t.cue_grid;
  md << "\n## Dynamic features against the ground-truth motion labels (paper: no such table)\n\n"
     << "Each variant traced at level full; a point is rejected when a stage's decision removes it "
     << "(P > tau_dyn), a line when its line-sample decision does (max(P_s, P_m, P_e) > tau_dyn). Truth: the "
     << "feature's pixel (a line's midpoint) belongs to a moving instance (`SEQ/gt/moving.txt`), or, for "
     << "'moving part', its pixel itself moves (`SEQ/gt/motion/`). Counts summed over all frames and seeds; "
     << "precision / recall / F1 in %. The full traces are deleted once counted (`RUN/rejection.json` keeps "
     << "the counts).\n\n"
     << "| Sequence | Variant | ATE RMSE (m) | points: precision | recall | F1 | points, moving part: precision | "
        "recall | F1 | lines: precision | recall | F1 | lines, moving part: precision | recall | F1 |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<RunSummary> total(cues.size());
  for (const std::string& preset : a.sequences)
    for (size_t v = 0; v < cues.size(); ++v) {
      const MgdCell& c = cue_grid[preset][v];
      const RunSummary& r = c.pr;
      md << "| " << preset << " | " << cues[v].label << " | " << MeanSd(c.ate) << " | "
         << Prf(r.tp, r.fp, r.fn) << " | " << Prf(r.part_tp, r.part_fp, r.part_fn) << " | "
         << Prf(r.line_tp, r.line_fp, r.line_fn) << " | " << Prf(r.line_part_tp, r.line_part_fp, r.line_part_fn)
         << " |\n";
      AddRejectionCounts(total[v], r);
    }
  md << "\n### All sequences together\n\n| Variant | points: precision | recall | F1 | points, moving part: "
        "precision | recall | F1 | lines: precision | recall | F1 | lines, moving part: precision | recall | F1 |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  size_t best = 1;
  for (size_t v = 0; v < cues.size(); ++v) {
    const RunSummary& s = total[v];
    md << "| " << cues[v].label << " | " << Prf(s.tp, s.fp, s.fn) << " | " << Prf(s.part_tp, s.part_fp, s.part_fn)
       << " | " << Prf(s.line_tp, s.line_fp, s.line_fn) << " | "
       << Prf(s.line_part_tp, s.line_part_fp, s.line_part_fn) << " |\n";
    if (v >= 1 && v <= 3 && F1(s.tp, s.fp, s.fn) > F1(total[best].tp, total[best].fp, total[best].fn)) best = v;
  }
  md << "\nSingle cue with the highest point F1 over all sequences: **" << cues[best].label << "**.\n";
}

// Table 6: per-module CPU ms per frame of mgd.
void MgdWriteModuleTimes(MgdRun& t, std::ostringstream& md) {
  const MgdTableArgs& a = t.a;
  auto& grid = t.grid;
  const PaperTable& p6 = t.p6;
  md << "\n## Per-module CPU ms per frame of MGD-SLAM (paper Table 6)\n\n"
     << "dynref: one core, thread CPU time, trace level frames (`run.json` `timing`, `timing_stages`), mean over "
     << "seeds. Feature extraction = ORB + lines (FLD + LBD) + planes (AHC); dynamic removal = the mgd.* stages "
     << "(boxes, probabilities, reprojection cue at keyframes); tracking total = extraction + tracking thread "
     << "(dynamic removal included; local mapping runs in the same thread here and is listed apart). No detector "
     << "runs: the boxes are synthetic (the paper's YOLO, asynchronous, 12 ms). The paper: AMD Ryzen 7 5800H.\n\n"
     << "| Sequence | ORB | lines | planes | feature extraction | dynamic removal | tracking total | "
        "local mapping + BA | paper extraction | paper removal | paper detection | paper tracking total |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& preset : a.sequences) {
    const MgdCell& c = grid[preset][2];
    const auto ms = [&](const char* m) { return c.ms.count(m) ? Mean(c.ms.at(m)) : std::nan(""); };
    const double ex = ms("extraction"), li = ms("lines"), pl = ms("planes"), st = ms("stages"), tr = ms("tracking");
    md << "| " << preset << " | " << Num(ex - li - pl, 1) << " | " << Num(li, 1) << " | " << Num(pl, 1) << " | "
       << Num(ex, 1) << " | " << Num(st, 1) << " | " << Num(ex + tr, 1) << " | "
       << Num(ms("local_mapping") + ms("ba"), 1) << " |";
    for (const char* row : {"Multi-granularity feature extraction", "Dynamic feature removal",
                            "Semantic detection (asynchronous)", "Total tracking time"})
      md << " " << Num(p6.Cell(row, "Average Time (ms)"), 0) << " |";
    md << "\n";
  }
}

// The ATE bars and the per-seed section; writes the report.
void FinishMgdReport(MgdRun& t, std::ostringstream& md) {
  const MgdTableArgs& a = t.a;
  const auto& main = t.main;
  auto& grid = t.grid;
  const PaperTable &p2 = t.p2, &p4 = t.p4;
  std::vector<SeedSeries> ours;
  std::vector<PaperSeries> paper;
  for (size_t v = 0; v < main.size(); ++v) {
    SeedSeries s{main[v].label, {}};
    for (const std::string& preset : a.sequences) s.per_group.push_back(grid[preset][v].ate);
    ours.push_back(s);
    const std::string col = a.table == "table2" ? main[v].paper2 : main[v].paper4;
    if (col.empty()) continue;
    PaperSeries p{"paper " + col, {}, v};
    for (const std::string& preset : a.sequences) p.per_group.push_back((a.table == "table2" ? p2 : p4).Cell(MgdPaperRow(preset), col));
    paper.push_back(p);
  }
  FinishAteReport(md.str(), a.sequences, ours, paper, 0, SeedListText(a.seeds), a.out);
}

}  // namespace

int RunMgdTable(const MgdTableArgs& a) {
  MgdCheckArgs(a);
  MgdRun t(a);
  t.p2 = ReadPaperTable(PaperTableDir() + "/000-table2.csv");
  t.p4 = ReadPaperTable(PaperTableDir() + "/000-table4.csv");
  t.p5 = ReadPaperTable(PaperTableDir() + "/000-table5.csv");
  t.p6 = ReadPaperTable(PaperTableDir() + "/000-table6.csv");
  MakeReportFolders(a.out, a.work);
  t.ablations = a.table == "table2" && !a.no_ablations;
  for (const MgdVariant& v : t.main) t.main_cfg.push_back(LoadConfigWithout(v.config, {}));
  for (const MgdVariant& v : t.cues) t.cue_cfg.push_back(LoadConfigWithout(v.config, {}));
  RunMgdMatrix(t);
  std::ostringstream md;
  MgdWriteIntro(t, md);
  if (a.table == "table2") {
    md << "## ATE RMSE (m) (paper Table 2)\n\n";
    WriteValueTable(t, md, false, t.p2, kPaperCols2);
    if (t.ablations) WriteCueAblations(t, md);
    md << PaperNotes("000-table2.csv", t.p2.notes);
  } else {
    md << "## ATE RMSE (m) (paper Table 4)\n\n";
    WriteValueTable(t, md, false, t.p4, kPaperCols4);
    md << "\n## RPE (paper Table 5)\n\n"
       << "dynref: translational RPE RMSE in m over 1 s (evaluate_rpe.py --fixed_delta --delta 1). The paper prints "
       << "'rad' and does not state its interval (see the notes), so only the ordering of the columns compares.\n\n";
    WriteValueTable(t, md, true, t.p5, kPaperCols4);
    MgdWriteModuleTimes(t, md);
    md << PaperNotes("000-table4.csv", t.p4.notes) << PaperNotes("000-table5.csv", t.p5.notes)
       << PaperNotes("000-table6.csv", t.p6.notes);
  }
  FinishMgdReport(t, md);
  return kExitOk;
}

void RegisterMgdTables(TableRegistry& registry) {
  const auto add = [](const std::string& table) {
    return [table](CLI::App& app) {
      auto m = std::make_shared<MgdTableArgs>();
      m->table = table;
      m->out = "reports/mgd-" + table + ".md";
      m->sequences = MgdTableDefaultSequences(table);
      MatrixHelp help;
      help.work = "Working folder <work>/seed<S>/{seq,runs}, shared by mgd-table2/4";
      help.detections = "Synthetic detection mode (default yolo-like)";
      help.sequences = "Presets (default the table's)";
      AddMatrixOptions(app, *m, help);
      if (table == "table2")
        app.add_flag("--no-ablations", m->no_ablations, "Skip the cue ablations and the precision/recall runs");
      AddReuseCollect(app, *m, "Reuse sequences/runs of an earlier call with identical inputs",
                      "Only read: sequences and runs already in --work");
      return TableCommand{m, [m] { return RunMgdTable(*m); }};
    };
  };
  registry.Add({"mgd-table2", "000 MGD-SLAM",
                "ATE of orb, mgd-nd and mgd on 8 walking/sitting analogues; dynamic point/line P/R/F1 per cue ablation",
                "MGD-SLAM Table 2: ATE of orb, mgd-nd, mgd on 8 synthetic walking/sitting analogues, and "
                "dynamic point/line precision/recall/F1 of mgd and its cue ablations, over seeds",
                add("table2")});
  registry.Add({"mgd-table4", "000 MGD-SLAM", "Tables 4-6: MGD-SLAM-nD ablation ATE and RPE on walking, per-module ms/frame",
                "MGD-SLAM Tables 4-6: MGD-SLAM-nD ablation ATE and RPE on the walking analogues, "
                "per-module ms/frame of mgd, over seeds",
                add("table4")});
}

}  // namespace dynref::reproduce
