#include "reproduce/sgdo_tables.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/version.h"
#include "reproduce/arg_checks.h"
#include "reproduce/paper_table.h"
#include "reproduce/report_format.h"
#include "reproduce/report_plots.h"
#include "reproduce/sgdo_table6.h"
#include "reproduce/workspace.h"
#include "synth/world.h"

namespace fs = std::filesystem;

namespace dynref::reproduce {
namespace {

constexpr size_t kOrb = 0, kSgdo = 1;
const char* const kConfigs[] = {"orb", "sgdo_nodense"};  // sgdo without its dense map (no effect on tracking)

using SgdoCell = std::vector<RunSummary>;  // one run per seed

// The statistic a table reports for one run; false when the run has none.
bool Stats(const std::string& table, const RunSummary& s, ErrorStats& out) {
  if (table == "table2" || table == "table3") {
    if (!s.has_rpe) return false;
    out = table == "table2" ? s.rpe_trans : s.rpe_rot;
    return true;
  }
  if (!s.has_ate) return false;
  out = s.ate;
  return true;
}

double Pick(const ErrorStats& e, size_t k) { return k == 0 ? e.rmse : k == 1 ? e.mean : k == 2 ? e.median : e.std; }
const char* const kStatNames[] = {"RMSE", "Mean", "Median", "S.D."};

std::string MachineText() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      std::string m = line.substr(line.find(':') + 1);
      m.erase(0, m.find_first_not_of(' '));
      return m;
    }
  return "unknown CPU";
}

void SgdoCheckArgs(const SgdoTableArgs& a) {
  const auto& t = SgdoMainTables();
  if (std::find(t.begin(), t.end(), a.table) == t.end()) throw InputError("table", "unknown table '" + a.table + "'");
  CheckMatrixArgs(a.frames, a.seeds, a.detections, a.sequences, a.reuse, a.collect);
  CheckReportPaths(a.out, a.work);
}

}  // namespace

const std::vector<std::string>& SgdoMainTables() {
  static const std::vector<std::string> t = {"table1", "table2", "table3", "table4", "table7"};
  return t;
}

namespace {

const std::map<std::string, std::string>& Titles() {
  static const std::map<std::string, std::string> titles = {
      {"table1", "Table 1: ATE (m)"},
      {"table2", "Table 2: translational RPE (m/s)"},
      {"table3", "Table 3: rotational RPE (deg/s)"},
      {"table4", "Table 4: ATE against the peer systems (m)"},
      {"table7", "Table 7: processing time per frame (ms)"}};
  return titles;
}

// The shared workspace of one SGDO table: its inputs, the runs, the plots beside the report.
struct SgdoRun {
  const SgdoTableArgs& a;
  PaperTable paper, t1;
  std::map<std::string, std::vector<SgdoCell>> cells;  // preset -> [orb, sgdo][seed]
  std::string stem;                                // the report's path without .md
  std::vector<std::pair<std::string, std::string>> plots;  // caption, file name beside the report
  std::map<std::string, std::string> titles = Titles();
  SgdoRun(const SgdoTableArgs& args, PaperTable p, PaperTable table1) : a(args), paper(std::move(p)), t1(std::move(table1)) {}
};

// Runs: orb and sgdo_nodense on every preset, seed by seed.
void RunCells(SgdoRun& r) {
  const SgdoTableArgs& a = r.a;
  auto& cells = r.cells;
  for (const std::string& p : a.sequences) cells[p].resize(2);
  const MethodConfig configs[] = {LoadMethodConfig(MethodConfigPath(kConfigs[0])),
                                  LoadMethodConfig(MethodConfigPath(kConfigs[1]))};
  for (uint64_t seed : a.seeds) {
    Workspace ws(SeedWorkDir(a.work, seed), {a.frames, seed, a.detections}, a.reuse,
                 a.collect ? WorkMode::kCollect : WorkMode::kMake);
    ws.set_keep_full_traces(false);  // counted into RUN/rejection.json: disk stays bounded at the papers' lengths
    for (const std::string& preset : a.sequences) {
      const std::string seq = ws.EnsureSequence(preset);
      for (size_t m = 0; m < 2; ++m)
        cells[preset][m].push_back(
            ws.Run(seq, preset + "/" + kConfigs[m], configs[m], m == kOrb ? "ORB-SLAM2" : "SGDO-SLAM"));
    }
  }
}

void SgdoWriteIntro(SgdoRun& r, std::ostringstream& md) {
  const SgdoTableArgs& a = r.a;
  const auto& cells = r.cells;
  const auto& titles = r.titles;
  std::string cmd = "dynref reproduce sgdo-" + a.table + " --frames " + std::to_string(a.frames) + " --seeds " +
                    SeedListText(a.seeds) + " --detections " + a.detections;
  if (a.sequences != SgdoTableArgs{}.sequences) {
    cmd += " --sequences ";
    for (size_t i = 0; i < a.sequences.size(); ++i) cmd += (i ? "," : "") + a.sequences[i];
  }
  md << "# SGDO-SLAM (seed 001) " << titles.at(a.table) << ", on synthetic sequences\n\n"
     << "Written by `" << cmd << "` (dynref " << DYNREF_VERSION << ", commit " << DYNREF_GIT_COMMIT
     << "). Do not edit by hand.\n\n"
     << "- Runs made by dynref commit " << [&] {
          std::vector<RunSummary> all;
          for (const auto& [preset, c] : cells)
            for (const SgdoCell& runs : c) all.insert(all.end(), runs.begin(), runs.end());
          return RunCommits(all);
        }() << ".\n"
     << "- Sequences: `dynref synth --preset P --frames " << a.frames << " --seed S --detections " << a.detections
     << "` for seeds S = " << SeedListText(a.seeds) << "; the paper ran one non-deterministic run on each full real "
     << "TUM sequence (frame counts below).\n"
     << "- Methods: ORB-SLAM2 = `configs/orb.yaml` (dynref's backbone), SGDO-SLAM = `configs/sgdo_nodense.yaml` "
     << "(`configs/sgdo.yaml` without the dense map, which does not feed back into tracking).\n"
     << "- dynref cells: mean ± population S.D. over the seeds; improvement = 100 (1 - SGDO / ORB) per seed, "
     << "then mean ± S.D. Paper values: `reports/paper-tables/001-" << a.table << ".csv`.\n\n"
     << FramesTable(a.sequences, a.frames, [&] {
          std::vector<std::string> rows;
          for (const std::string& p : a.sequences) rows.push_back(PaperRows(p).second);
          return rows;
        }());
}

// Tables 1-3: ATE / RPE statistics of orb and sgdo and the improvements, per sequence.
void WriteStatsTable(SgdoRun& r, std::ostringstream& md) {
  const SgdoTableArgs& a = r.a;
  auto& cells = r.cells;
  const auto& titles = r.titles;
  const PaperTable& paper = r.paper;
  md << "\n## " << titles.at(a.table) << "\n\n| Sequence | source |";
  for (const char* m : {"ORB-SLAM2", "SGDO-SLAM", "Improvement"})
    for (const char* s : kStatNames) md << " " << m << " " << s << (std::string(m) == "Improvement" ? " (%)" : "") << " |";
  md << " tracked (ORB / SGDO) |\n|---|---|";
  for (int i = 0; i < 12; ++i) md << "---|";
  md << "---|\n";
  const int dec = 4;
  for (const std::string& preset : a.sequences) {
    const std::string row = PaperRows(preset).second;
    std::vector<double> vals[2][4], imp[4];
    int tracked[2] = {0, 0}, frames = 0;
    for (size_t k = 0; k < a.seeds.size(); ++k) {
      ErrorStats e[2];
      bool ok[2];
      for (size_t m = 0; m < 2; ++m) {
        const RunSummary& s = cells[preset][m][k];
        ok[m] = Stats(a.table, s, e[m]);
        tracked[m] += s.tracked;
        if (ok[m])
          for (size_t st = 0; st < 4; ++st) vals[m][st].push_back(Pick(e[m], st));
      }
      frames += cells[preset][0][k].frames;
      if (ok[0] && ok[1])
        for (size_t st = 0; st < 4; ++st) imp[st].push_back(100.0 * (1.0 - Pick(e[1], st) / Pick(e[0], st)));
    }
    md << "| " << preset << " | dynref |";
    for (size_t m = 0; m < 2; ++m)
      for (size_t st = 0; st < 4; ++st) md << " " << MeanSd(vals[m][st], dec) << " |";
    for (size_t st = 0; st < 4; ++st) md << " " << MeanSd(imp[st], 1) << " |";
    md << " " << tracked[0] << " / " << tracked[1] << " of " << frames << " |\n| " << row << " | paper |";
    for (const char* m : {"ORB-SLAM2", "SGDO-SLAM"})
      for (const char* s : kStatNames) md << " " << Num(paper.Cell(row, std::string(m) + " " + s)) << " |";
    for (const char* s : kStatNames) md << " " << Num(paper.Cell(row, std::string("Improvement ") + s + " (%)"), 2) << " |";
    md << " |\n";
  }
}

// Tables 1-3: bars of dynref orb and sgdo (mean +- S.D. over seeds) beside the paper's, per sequence.
void PlotStatsTable(SgdoRun& r) {
  const SgdoTableArgs& a = r.a;
  auto& cells = r.cells;
  const auto& titles = r.titles;
  const PaperTable& paper = r.paper;
  const std::string& stem = r.stem;
  auto& plots = r.plots;
  const std::string unit = a.table == "table1" ? "ATE RMSE [m]" : a.table == "table2" ? "RPE RMSE [m/s]" : "RPE RMSE [deg/s]";
  std::vector<render::BarSeries> series(4);
  series[0] = {"dynref ORB-SLAM2", {}, {}, render::SeriesColour(4)};
  series[1] = {"dynref SGDO-SLAM", {}, {}, render::SeriesColour(5)};
  series[2] = {"paper ORB-SLAM2", {}, {}, Lighter(render::SeriesColour(4))};
  series[3] = {"paper SGDO-SLAM", {}, {}, Lighter(render::SeriesColour(5))};
  for (const std::string& preset : a.sequences) {
    for (size_t m = 0; m < 2; ++m) {
      std::vector<double> r;
      ErrorStats e;
      for (const RunSummary& s : cells[preset][m])
        if (Stats(a.table, s, e)) r.push_back(e.rmse);
      series[m].value.push_back(Mean(r));
      series[m].error.push_back(r.size() > 1 ? ComputeErrorStats(r).std : std::nan(""));
      series[2 + m].value.push_back(paper.Cell(PaperRows(preset).second, std::string(m == kOrb ? "ORB-SLAM2" : "SGDO-SLAM") + " RMSE"));
    }
  }
  render::BarChartOptions bo;
  bo.title = titles.at(a.table) + ", RMSE: mean +- S.D. over seeds " + SeedListText(a.seeds);
  bo.y_label = unit;
  bo.log_y = true;
  PlotBars(a.sequences, series, bo, stem + ".png");
  plots.push_back({titles.at(a.table), fs::path(stem + ".png").filename().string()});
}

// Table 4: the peers' printed ATE beside dynref's orb and sgdo.
void WritePeerTable(SgdoRun& r, std::ostringstream& md) {
  const SgdoTableArgs& a = r.a;
  auto& cells = r.cells;
  const auto& titles = r.titles;
  const PaperTable& paper = r.paper;
  md << "\n## " << titles.at(a.table) << "\n\n"
     << "The peer systems were not run by dynref: their columns are the paper's printed values (paper, not run). "
        "dynref's SGDO-SLAM and ORB-SLAM2 are synthetic analogues, mean ± S.D. over seeds.\n\n";
  std::vector<std::string> peers;
  for (const std::string& h : paper.header)
    if (h.size() > 5 && h.compare(h.size() - 5, 5, " RMSE") == 0) peers.push_back(h.substr(0, h.size() - 5));
  md << "| Sequence |";
  for (const std::string& p : peers) md << " " << p << " RMSE (paper" << (p == "SGDO-SLAM" ? "" : ", not run") << ") |";
  md << " dynref ORB-SLAM2 RMSE | dynref SGDO-SLAM RMSE | dynref SGDO-SLAM S.D. |\n|---|";
  for (size_t i = 0; i < peers.size() + 3; ++i) md << "---|";
  md << "\n";
  for (const std::string& preset : a.sequences) {
    const std::string row = PaperRows(preset).first;
    md << "| " << preset << " (" << row << ") |";
    for (const std::string& p : peers) md << " " << Num(paper.Cell(row, p + " RMSE")) << " |";
    std::vector<double> orb, sgdo, sd;
    for (size_t k = 0; k < a.seeds.size(); ++k) {
      if (cells[preset][kOrb][k].has_ate) orb.push_back(cells[preset][kOrb][k].ate.rmse);
      if (cells[preset][kSgdo][k].has_ate)
        sgdo.push_back(cells[preset][kSgdo][k].ate.rmse), sd.push_back(cells[preset][kSgdo][k].ate.std);
    }
    md << " " << MeanSd(orb) << " | " << MeanSd(sgdo) << " | " << MeanSd(sd) << " |\n";
  }
  md << "\nPaper's SGDO-SLAM column here equals its Table 6 (S+G+D+O) and differs from its Table 1 on "
        "fr3_w_xyz and fr3_w_half (see `reports/paper-tables/001-table1.csv`).\n";
}

// Table 7: CPU ms per frame, per module, with the machine named.
void WriteTimingTable(SgdoRun& r, std::ostringstream& md) {
  const SgdoTableArgs& a = r.a;
  auto& cells = r.cells;
  const auto& titles = r.titles;
  const PaperTable& paper = r.paper;
  const std::string& stem = r.stem;
  auto& plots = r.plots;
  const std::string machine = MachineText();  // /proc/cpuinfo, read once
  std::vector<double> slam[2], total[2];
  for (const std::string& preset : a.sequences)
    for (size_t m = 0; m < 2; ++m)
      for (const RunSummary& s : cells[preset][m]) {
        if (std::isfinite(s.ms_slam)) slam[m].push_back(s.ms_slam);
        if (std::isfinite(s.ms_total)) total[m].push_back(s.ms_total);
      }
  md << "\n## " << titles.at(a.table) << "\n\n"
     << "dynref: thread CPU time on one core (`run.json` `timing`), mean ± S.D. over every sequence and seed "
     << "above; SLAM = everything after image decoding (tracking, method stages, local mapping, BA), total adds "
     << "PNG decoding. The masks are precomputed synthetic detections: no segmentation network time is "
        "included (the paper's 38.81 ms includes YOLOv8-seg on a GPU). Runs keep a full trace, whose writing "
        "is included. Machine: "
     << machine << ". These numbers change with the machine and its load; the rest of the report does not.\n\n"
     << "| System | ms per frame | hardware | source |\n|---|---|---|---|\n";
  for (const auto& row : paper.ordered)
    if (row.size() >= 3) md << "| " << row[0] << " | " << row[1] << " | " << row[2] << " | paper" << (row[0].rfind("SGDO", 0) == 0 || row[0] == "ORB-SLAM2" ? "" : " (not run by dynref)") << " |\n";
  for (size_t m = 0; m < 2; ++m)
    md << "| dynref " << (m == kOrb ? "ORB-SLAM2 (orb)" : "SGDO-SLAM (sgdo_nodense)") << " | SLAM " << MeanSd(slam[m], 2)
       << ", total " << MeanSd(total[m], 2) << " | " << machine << ", 1 thread | dynref |\n";
  // Per-module bars (run.json timing modules, method stages summed) of orb and sgdo.
  const std::vector<std::pair<std::string, std::string>> modules = {
      {"load", "load"}, {"extraction", "extraction"}, {"stages", "stages"}, {"tracking", "tracking"},
      {"local_mapping", "mapping"}, {"ba", "BA"}, {"slam", "SLAM"}};
  std::vector<render::BarSeries> series = {{"dynref ORB-SLAM2", {}, {}, render::SeriesColour(4)},
                                           {"dynref SGDO-SLAM", {}, {}, render::SeriesColour(5)}};
  std::vector<std::string> groups;
  md << "\n### Per module, ms per frame (dynref, mean ± S.D. over sequences and seeds)\n\n| module | ORB-SLAM2 | SGDO-SLAM |\n|---|---|---|\n";
  for (const auto& [key, label] : modules) {
    groups.push_back(label);
    md << "| " << label << " |";
    for (size_t m = 0; m < 2; ++m) {
      std::vector<double> v;
      for (const std::string& preset : a.sequences)
        for (const RunSummary& s : cells[preset][m])
          if (s.ms_modules.count(key)) v.push_back(s.ms_modules.at(key));
      series[m].value.push_back(Mean(v));
      series[m].error.push_back(v.size() > 1 ? ComputeErrorStats(v).std : std::nan(""));
      md << " " << MeanSd(v, 2) << " |";
    }
    md << "\n";
  }
  md << "\nrun.json `timing` modules: load = PNG decoding, stages = the method's stages summed (`timing_stages`), "
        "tracking includes the stages, mapping = local mapping, BA = local bundle adjustment, SLAM = everything after load.\n";
  render::BarChartOptions bo;
  bo.title = "CPU ms per frame per module (" + machine + ")";
  bo.y_label = "ms per frame";
  PlotBars(groups, series, bo, stem + ".png");
  plots.push_back({"Per-module CPU time", fs::path(stem + ".png").filename().string()});
}

void WritePerSeed(SgdoRun& r, std::ostringstream& md) {
  const SgdoTableArgs& a = r.a;
  auto& cells = r.cells;
  md << "\n## Per seed (" << SeedListText(a.seeds) << "): " << (a.table == "table7" ? "SLAM ms per frame" : a.table == "table2" ? "translational RPE RMSE (m/s)" : a.table == "table3" ? "rotational RPE RMSE (deg/s)" : "ATE RMSE (m)")
     << ", tracked frames\n\n| Sequence | ORB-SLAM2 | SGDO-SLAM |\n|---|---|---|\n";
  for (const std::string& preset : a.sequences) {
    md << "| " << preset << " |";
    for (size_t m = 0; m < 2; ++m) {
      for (const RunSummary& s : cells[preset][m]) {
        ErrorStats e;
        const std::string v = a.table == "table7" ? Num(s.ms_slam, 2) : (Stats(a.table, s, e) ? Num(e.rmse) : "n/a");
        md << " " << v << " (" << s.tracked << ")";
      }
      md << " |";
    }
    md << "\n";
  }
}

}  // namespace

int RunSgdoTable(const SgdoTableArgs& a) {
  SgdoCheckArgs(a);
  SgdoRun r(a, ReadPaperTable(PaperTableDir() + "/001-" + a.table + ".csv"),
            ReadPaperTable(PaperTableDir() + "/001-table1.csv"));
  const fs::path report_dir = fs::path(a.out).parent_path();
  if (!report_dir.empty()) fs::create_directories(report_dir);
  if (!a.collect) fs::create_directories(a.work);
  RunCells(r);
  r.stem = (report_dir / fs::path(a.out).stem()).string();
  std::ostringstream md;
  SgdoWriteIntro(r, md);
  if (a.table == "table1" || a.table == "table2" || a.table == "table3") {
    WriteStatsTable(r, md);
    PlotStatsTable(r);
    if (a.table != "table1")
      md << "\nRPE: every pair (i, j) with stamp_j closest to stamp_i + 1 s (evaluate_rpe.py --fixed_delta, no "
            "random sub-sampling); the paper does not state its interval, m/s implies 1 s.\n";
  } else if (a.table == "table4") {
    WritePeerTable(r, md);
  } else {  // table7
    WriteTimingTable(r, md);
  }
  md << PaperNotes("001-" + a.table + ".csv", r.paper.notes);
  if (!r.plots.empty()) {
    md << "\n## Plots\n\nBars: dynref's mean over seeds with its S.D.; the paper's values in the lighter bars.\n";
    for (const auto& [caption, file] : r.plots) md << "\n![" << caption << "](" << file << ")\n";
  }
  WritePerSeed(r, md);
  AtomicWriteFile(a.out, md.str());
  std::cout << "reproduce: wrote " << a.out << "\n";
  return kExitOk;
}

void RegisterSgdoTables(TableRegistry& registry) {
  const std::map<std::string, std::string> what = {
      {"table1", "ATE RMSE/mean/median/S.D. of orb and sgdo, improvements, over seeds"},
      {"table2", "translational RPE (1 s, m/s) of orb and sgdo, improvements, over seeds"},
      {"table3", "rotational RPE (1 s, deg/s) of orb and sgdo, improvements, over seeds"},
      {"table4", "ATE of sgdo beside the peer systems' printed values (peers not run)"},
      {"table7", "CPU ms per frame of orb and sgdo beside the paper's systems"}};
  for (const std::string& table : SgdoMainTables())
    registry.Add({"sgdo-" + table, "001 SGDO-SLAM", what.at(table), "SGDO-SLAM " + table + ": " + what.at(table),
                  [table](CLI::App& app) {
                    auto t = std::make_shared<SgdoTableArgs>();
                    t->table = table;
                    t->out = "reports/sgdo-" + table + ".md";
                    MatrixHelp help;
                    help.work = "Working folder <work>/seed<S>/{seq,runs}, shared with sgdo-table6";
                    help.detections = "Synthetic detection mode (default yolo-like)";
                    help.sequences = "Presets (default the five of the paper's TUM tables)";
                    AddMatrixOptions(app, *t, help);
                    AddReuseCollect(app, *t, "Reuse sequences/runs of an earlier call with identical inputs",
                                    "Only read: sequences and runs were made by dynref synth/run (workflow/Snakefile)");
                    return TableCommand{t, [t] { return RunSgdoTable(*t); }};
                  }});
}

}  // namespace dynref::reproduce
