// `dynref eval --gt G --est E`: ATE and RPE as TUM's evaluate_ate.py / evaluate_rpe.py and evo.
#include <iostream>

#include "cli/command.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/trajectory_report.h"

namespace dynref::cli {
namespace {

// Reads, computes and words the report in eval/trajectory_report.h; here: print and write.
int RunEval(const TrajectoryEvalOptions& a, const std::string& json, const std::string& save_rpe) {
  const TrajectoryEvalReport report = EvaluateTrajectoryFiles(a, std::cout);
  std::cout << TrajectoryReportText(report);
  if (!save_rpe.empty()) WriteRpePairs(save_rpe, report.est, report.rpe);
  if (!json.empty()) AtomicWriteFile(json, TrajectoryReportJson(report));
  return kExitOk;
}

struct EvalArgs {
  TrajectoryEvalOptions options;
  std::string json, save_rpe;
};

}  // namespace

void RegisterEvalCommand(CLI::App& root, CommandList& out) {
  auto args = std::make_shared<EvalArgs>();
  TrajectoryEvalOptions& o = args->options;
  CLI::App* app = root.add_subcommand(
      "eval",
      "ATE and RPE of an estimated TUM trajectory against ground truth; reproduces TUM's "
      "evaluate_ate.py / evaluate_rpe.py (--assoc tum) and evo_ape -a (--assoc evo)");
  app->add_option("--gt", o.gt, "Ground-truth TUM trajectory (stamp tx ty tz qx qy qz qw)")
      ->required();
  app->add_option("--est", o.est, "Estimated TUM trajectory")->required();
  app->add_option("--max-diff", o.max_diff, "Association max time difference in s")
      ->capture_default_str();
  app->add_option("--offset", o.offset,
                  "Time offset in s added to the estimate's stamps before matching ground truth "
                  "(evaluate_ate.py / evaluate_rpe.py --offset, evo --t_offset)")
      ->capture_default_str();
  app->add_option("--assoc", o.assoc,
                  "tum: associate.py greedy one-to-one (evaluate_ate.py); evo: nearest "
                  "neighbour as evo_ape --t_max_diff")
      ->check(CLI::IsMember({"tum", "evo"}))
      ->capture_default_str();
  app->add_option("--align", o.align,
                  "ATE alignment: se3 (evaluate_ate.py, evo_ape -a), sim3 (evo_ape -as), none")
      ->check(CLI::IsMember({"se3", "sim3", "none"}))
      ->capture_default_str();
  app->add_option("--delta", o.delta, "RPE fixed delta (evaluate_rpe.py --delta)")
      ->capture_default_str();
  app->add_option("--delta-unit", o.delta_unit, "RPE delta unit: s (seconds) or f (frames)")
      ->check(CLI::IsMember({"s", "f"}))
      ->capture_default_str();
  app->add_option("--rpe-mode", o.rpe_mode,
                  "RPE pairs: tum = evaluate_rpe.py --fixed_delta, every pair; interp = the same "
                  "pairs plus the one ending at the last pose, ground truth interpolated at the "
                  "stamps (lerp + slerp)")
      ->check(CLI::IsMember({"tum", "interp"}))
      ->capture_default_str();
  app->add_option("--save-rpe", args->save_rpe,
                  "Write every RPE pair as evaluate_rpe.py --save does: stamp_est0 stamp_est1 "
                  "stamp_gt0 stamp_gt1 trans_error[m] rot_error[rad] (atomically)");
  app->add_option("--json", args->json, "Also write the results as JSON (atomically)");
  out.push_back({app, [args] { return RunEval(args->options, args->json, args->save_rpe); }});
}

}  // namespace dynref::cli
