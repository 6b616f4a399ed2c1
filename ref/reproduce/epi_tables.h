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

namespace dynref::reproduce {

struct EpiTableArgs {
  std::string table;             // "table1" | "table2"
  std::string out;               // default reports/epi-<table>.md
  std::string work = "dynref-work/epi";
  int frames = 60;
  int gap = 5;                   // table2: frame distance of a pair
  int features = 500;            // table2: features per image (paper Sec. 4.2: 500)
  double correct_px = 3.0;       // table2: a match is correct within this distance of the truth (not stated)
  std::vector<uint64_t> seeds = {1, 2, 3};
  bool reuse = false;
};

int RunEpiTable(const EpiTableArgs& args);

}  // namespace dynref::reproduce
