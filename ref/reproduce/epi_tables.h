// `dynref reproduce epi-table1` and `epi-table2`: seed 004's feature experiments on synthetic
// static scenes, where every correspondence is known exactly (depth + ground-truth poses).
//   epi-table1: keypoints per frame of ORB and SIFT on raw and enhanced (Module A) grey images,
//               normal and --low-light renderings (paper Table 1: points on a weak-texture image).
//   epi-table2: matching of frame pairs (k, k + gap) by ORB + BF, ORB + MNN2, SIFT + BF,
//               SIFT + MNN2: correct matches, precision against the exact correspondences, CPU
//               time (paper Table 2, where ZippyPoint takes SIFT's place here: dynref has no
//               ZippyPoint weights, issue 17 Module B).
// Typologies (Table 2 rows): light change (normal frame k vs low-light frame k + gap), rotation
// (static_rpy), perspective (static_halfsphere), motion blur (--blur), low light (both dark).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "reproduce/table_registry.h"

namespace dynref::reproduce {

struct EpiTableArgs : MatrixArgs {  // no detections, sequences or --collect
  EpiTableArgs() {
    work = "dynref-work/epi";
    frames = 60;
  }
  std::string table;        // "table1" | "table2"; out: reports/epi-<table>.md
  int gap = 5;              // table2: frame distance of a pair
  int features = 500;       // table2: features per image (paper Sec. 4.2: 500)
  double correct_px = 3.0;  // table2: a match is correct within this distance of the truth (not stated)
};

int RunEpiTable(const EpiTableArgs& args);
// epi-table1, epi-table2 and their options.
void RegisterEpiTables(TableRegistry& registry);

}  // namespace dynref::reproduce
