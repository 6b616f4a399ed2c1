// `dynref reproduce epi-table3`: seed 004's SLAM tables on synthetic analogues of the TUM fr3 and
// Bonn sequences, rendered normally and with --low-light, over several synthesis seeds:
//   Table 3: mean / median / RMSE / S.D. of the ATE of epi (A + C) per sequence;
//   Tables 4-5: ATE RMSE of orb, epi (A + C) and epi_ALL (A + B + C) beside the paper's
//            ORB-SLAM3 and OURS;
//   Table 6: the module ablation None (orb) / A / B / C / A + C / B + C / ALL (B = SIFT + MNN2,
//            issue 17);
//   mask vote: Module C's per-mask decisions against the ground-truth motion labels (accuracy,
//            precision / recall of "dynamic", still people kept, moving objects removed);
//   Table 7: per-module CPU ms per frame of epi and epi_ALL (separate runs at trace level frames).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "reproduce/table_registry.h"

namespace dynref::reproduce {

struct EpiSlamTableArgs : MatrixArgs {  // sequences: default EpiSlamDefaultSequences()
  EpiSlamTableArgs() {
    out = "reports/epi-table3.md";
    work = "dynref-work/epi-slam";
  }
  std::vector<std::string> ablation_sequences;  // default: walking_static, crowd (paper Table 6)
  std::string timing_sequence = "walking_xyz";  // Table 7 runs
};

std::vector<std::string> EpiSlamDefaultSequences();
std::vector<std::string> EpiSlamDefaultAblationSequences();
// Checks every argument first (InputError naming the option), then runs and writes the report.
int RunEpiSlamTable(const EpiSlamTableArgs& args);
// epi-table3 and its options.
void RegisterEpiSlamTables(TableRegistry& registry);

}  // namespace dynref::reproduce
