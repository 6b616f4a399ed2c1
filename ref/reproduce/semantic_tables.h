// `dynref reproduce semantic-filesizes`: semantic mapping (seed 002) on synthetic analogues of its
// sequences, over seeds: the map files per stage (raw, SOR, voxel, octree, 2-D grid) beside the
// paper's sizes (Sec. 4.4, reports/paper-tables/002-filesizes.csv); map quality against the
// synthetic scene truth (`dynref map-eval`: accuracy, completeness, ghost fraction) of the
// semantic map, the same mapping on the plain backbone without removal (semantic_orbmap) and
// SGDO-SLAM's dense map; and the non-prior dynamic decisions (interaction test, replayed with the
// stage's own code) against the ground-truth motion of each detected object.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "reproduce/table_registry.h"

namespace dynref::reproduce {

struct SemanticTableArgs : MatrixArgs {
  SemanticTableArgs() {
    out = "reports/semantic-filesizes.md";
    work = "dynref-work/semantic";
    frames = 150;
    sequences = {"walking_xyz",    "walking_static",     "walking_rpy", "walking_halfsphere",
                 "sitting_static", "sitting_halfsphere", "static_rpy",  "moving_box"};
  }
};

int RunSemanticTable(const SemanticTableArgs& args);
// semantic-filesizes and its options.
void RegisterSemanticTables(TableRegistry& registry);

}  // namespace dynref::reproduce
