// `dynref eval` without the command line: ATE + RPE of one estimate against ground truth, read,
// computed and reported as TUM's evaluate_ate.py / evaluate_rpe.py and evo (trajectory_eval.h).
// The cli (cli/cmd_eval.cpp) only parses the options into TrajectoryEvalOptions and prints.
#pragma once
#include <ostream>
#include <string>

#include "eval/trajectory_eval.h"

namespace dynref {

// The options as `dynref eval` spells them (strings checked by the CLI's IsMember).
struct TrajectoryEvalOptions {
  std::string gt, est;                // TUM trajectory files
  double max_diff = 0.02;             // association |dt| limit, s
  double offset = 0.0;                // added to the estimate's stamps, s
  std::string assoc = "tum";          // tum | evo
  std::string align = "se3";          // se3 | sim3 | none
  double delta = 1.0;                 // RPE fixed delta
  std::string delta_unit = "s";       // s | f
  std::string rpe_mode = "tum";       // tum | interp
};

struct TrajectoryEvalReport {
  TrajectoryEvalOptions options;
  AteOptions ate_options;
  RpeOptions rpe_options;
  TumTrajectory gt, est;          // read as TUM's tools (later of two equal stamps kept): RPE
  TumTrajectory gt_ate, est_ate;  // read for ATE (evo association: every line kept)
  AteResult ate;
  RpeResult rpe;
};

// Checks the options, reads both files, computes ATE and RPE. When RPE fails with an InputError
// the ATE lines are written to `partial` before the error is rethrown (issue 20 item 10).
TrajectoryEvalReport EvaluateTrajectoryFiles(const TrajectoryEvalOptions& options, std::ostream& partial);

// The text `dynref eval` prints (inputs, association, alignment, ATE row, RPE rows).
std::string TrajectoryReportText(const TrajectoryEvalReport& report);

// The `--json` document (2-space indented, newline-terminated).
std::string TrajectoryReportJson(const TrajectoryEvalReport& report);

}  // namespace dynref
