// `dynref reproduce sgdo-table6`: the SGDO-SLAM ablation (seed 001, Table 6) on synthetic
// analogues of the TUM sequences, end to end: synthesise each sequence with detections, run orb +
// every sgdo variant (configs/sgdo*.yaml, configs as data: no YAML is edited), ATE (TUM
// evaluate_ate.py semantics, ref/eval), precision/recall of the rejected features against the
// synthetic ground-truth motion labels, ATE sensitivity to eta and lambda, an overlay montage of
// a walking frame, and a Markdown report with the paper's numbers beside ours
// (reports/paper-tables/001-table{1,6}.csv). Everything written is deterministic (no clock).
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/method_config.h"
#include "reproduce/table_registry.h"

namespace dynref::reproduce {

// MatrixArgs::work: <work>/seed<S>/{seq,runs}/ (the layout workflow/Snakefile writes; shared with
// sgdo-table1..7); collect: read sequences and runs made by workflow/Snakefile.
struct Table6Args : MatrixArgs {
  Table6Args() {
    out = "reports/sgdo-table6.md";
    work = "dynref-work/sgdo";
    sequences = {"walking_xyz", "walking_static", "walking_rpy", "walking_halfsphere", "sitting_static"};
  }
  std::vector<std::string> sensitivity = {"walking_xyz"};
  std::vector<std::string> variants;  // config names of Table6Variants() to run (empty = all)
  bool no_overlay = false;
};

// One column of the table: a config (configs/<config_name>.yaml, run into runs/<preset>/<config_name>),
// its label, and the paper's column prefix in Table 6 ("" = not in Table 6).
struct Variant {
  std::string config_name, label, paper;
  MethodConfig Config() const;
};
const std::vector<Variant>& Table6Variants();
constexpr size_t kFullVariant = 7;  // (S+G+D+O) in Table6Variants()
// (eta, lambda) pairs of the sensitivity sweep, and the (S+G+D+O) config with those values.
std::vector<std::pair<double, double>> SensitivityGrid();
MethodConfig SensitivityConfig(double eta, double lambda);

// Paper row names of a synthetic preset (Table 6, Table 1); empty when it has none.
std::pair<std::string, std::string> PaperRows(const std::string& preset);

// Checks every argument first (InputError naming the option), then runs and writes the report.
int RunSgdoTable6(const Table6Args& args);
// sgdo-table6 and its options.
void RegisterSgdoTable6(TableRegistry& registry);

}  // namespace dynref::reproduce
