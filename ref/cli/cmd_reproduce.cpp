// `dynref reproduce <table>`: argument parsing only; the tables live in ref/reproduce.
#include <memory>

#include "cli/command.h"
#include "reproduce/sgdo_table6.h"

namespace dynref::cli {

void RegisterReproduceCommand(CLI::App& root, CommandList& out) {
  CLI::App* rep = root.add_subcommand("reproduce", "Reproduce a paper table end to end on synthetic data");
  rep->require_subcommand(1);
  auto a = std::make_shared<reproduce::Table6Args>();
  auto seed = std::make_shared<std::string>(std::to_string(a->seed));
  CLI::App* app = rep->add_subcommand(
      "sgdo-table6", "SGDO-SLAM Table 6 (ablation): synth + orb + every sgdo variant + ATE + P/R + Markdown");
  app->add_option("--out", a->out, "Markdown report (default reports/sgdo_table6.md)");
  app->add_option("--work", a->work, "Working folder for sequences and runs (default dynref-work/sgdo-table6)");
  app->add_option("--frames", a->frames, "Frames per synthetic sequence (default 300)");
  app->add_option("--seed", *seed, "Synthesis seed (default 1; 0..2^64-1)");
  app->add_option("--detections", a->detections,
                  "Synthetic detection mode: ideal | yolo-like | sparseinst-like (default yolo-like)");
  app->add_option("--sequences", a->sequences, "Presets (default the five of Table 6)")->delimiter(',');
  app->add_option("--sensitivity", a->sensitivity, "Presets for the eta/lambda sweep (default walking_xyz; 'none' = skip)")
      ->delimiter(',');
  app->add_flag("--reuse", a->reuse, "Reuse sequences/runs of an earlier call with identical inputs");
  app->add_flag("--no-overlay", a->no_overlay, "Skip the overlay montage");
  out.push_back({app, [a, seed] {
                   a->seed = ParseSeed(*seed, "--seed");
                   if (a->sensitivity.size() == 1 && a->sensitivity[0] == "none") a->sensitivity.clear();
                   return reproduce::RunSgdoTable6(*a);
                 }});
}

}  // namespace dynref::cli
