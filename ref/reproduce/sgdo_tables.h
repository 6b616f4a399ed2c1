// `dynref reproduce sgdo-table1|2|3|4|7`: SGDO-SLAM (seed 001) against ORB-SLAM2 on the synthetic
// analogues of the paper's TUM sequences, over several synthesis seeds, from the same runs:
//   table1: ATE RMSE / mean / median / S.D. and improvements (TUM evaluate_ate.py);
//   table2: translational RPE over 1 s, m/s (evaluate_rpe.py --fixed_delta --delta 1);
//   table3: rotational RPE over 1 s, deg/s;
//   table4: the peer systems' ATE as printed (not run, marked so) beside dynref's SGDO-SLAM;
//   table7: CPU ms per frame of dynref's orb and sgdo (machine-dependent, stated with the machine).
// The runs are those of sgdo-table6 (same work folder layout <work>/seed<S>/runs/<preset>/<config>),
// so `--reuse` or the workflow's matrix serves every SGDO table.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "reproduce/table_registry.h"

namespace dynref::reproduce {

struct SgdoTableArgs : MatrixArgs {
  SgdoTableArgs() {
    work = "dynref-work/sgdo";
    sequences = {"walking_xyz", "walking_static", "walking_rpy", "walking_halfsphere", "sitting_static"};
  }
  std::string table;  // "table1" | "table2" | "table3" | "table4" | "table7"; out: reports/sgdo-<table>.md
};

const std::vector<std::string>& SgdoMainTables();  // table1, table2, table3, table4, table7
// Checks every argument first (InputError naming the option), then runs and writes the report.
int RunSgdoTable(const SgdoTableArgs& args);
// sgdo-table1, 2, 3, 4, 7 and their options.
void RegisterSgdoTables(TableRegistry& registry);

}  // namespace dynref::reproduce
