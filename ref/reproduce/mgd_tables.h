// `dynref reproduce mgd-table2` and `mgd-table4`: MGD-SLAM (seed 000) on synthetic analogues of
// the TUM fr3 walking / sitting sequences, with yolo-like boxes, over several synthesis seeds.
//   mgd-table2: ATE of orb, mgd-nd and mgd on the 8 sequences of paper Table 2, and the
//               dynamic-feature precision / recall / F1 (points and lines, against the
//               ground-truth motion labels) of mgd and of its cue ablations (only P_LS, only
//               P_pro, only P_mf, no diffusion), whose ATE is reported too.
//   mgd-table4: the MGD-SLAM-nD ablation on the walking sequences: ATE (Table 4), RPE (Table 5)
//               and per-module ms/frame of mgd (Table 6).
// Both share --work (default dynref-work/mgd): with --reuse the second reuses the first's runs.
// Reports are deterministic apart from the ms/frame table (CPU time, stated as such).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "reproduce/table_registry.h"

namespace dynref::reproduce {

struct MgdTableArgs : MatrixArgs {  // sequences: default the table's presets
  MgdTableArgs() { work = "dynref-work/mgd"; }
  std::string table;          // "table2" | "table4"; out: reports/mgd-<table>.md
  bool no_ablations = false;  // table2: skip the cue ablations and precision/recall runs
};

std::vector<std::string> MgdTableDefaultSequences(const std::string& table);
// Checks every argument first (InputError naming the option), then runs and writes the report.
int RunMgdTable(const MgdTableArgs& args);
// mgd-table2, mgd-table4 and their options.
void RegisterMgdTables(TableRegistry& registry);

}  // namespace dynref::reproduce
