// `dynref reproduce blur-table1` and `blur-table3`: motion-blur SLAM (seed 003) on synthetic
// analogues of its sequences, rendered with motion blur and with sparseinst-like masks that drop
// and shrink fast people (datasets/README.md), over several synthesis seeds.
//   blur-table1: ATE of ORB-SLAM2, SGDO-SLAM (dynref's, as a strong reference) and the method on
//                the TUM walking/sitting analogues (paper Table 1) and the Bonn-like presets
//                (Table 2), paper values beside ours.
//   blur-table3: the ablation (Table 3: w/o compensation, w/o depth, w/o probability), per-module
//                ms/frame (Table 4), compensation and depth fusion measured against the true
//                person pixels, and sweeps of dilation_size (Fig. 12) and theta on one sequence.
// Reports are deterministic apart from the ms/frame tables (CPU time, stated as such).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "reproduce/table_registry.h"

namespace dynref::reproduce {

struct BlurTableArgs : MatrixArgs {
  BlurTableArgs() {
    work = "dynref-work/blur";  // both tables: with --reuse the second reuses sequences and blur runs
    detections = "sparseinst-like";
  }
  std::string table;  // "table1" | "table3"; out: reports/blur-<table>.md; sequences: the table's presets
  bool blur = true;   // --no-blur renders sharp frames (then masks drop as without blur)
  std::vector<std::string> sweep = {"walking_xyz"};  // table3: dilation/theta sweeps ('none' = skip)
};

std::vector<std::string> BlurTableDefaultSequences(const std::string& table);
// Checks every argument first (InputError naming the option), then runs and writes the report.
int RunBlurTable(const BlurTableArgs& args);
// blur-table1, blur-table3 and their options.
void RegisterBlurTables(TableRegistry& registry);

}  // namespace dynref::reproduce
