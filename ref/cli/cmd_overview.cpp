// `dynref overview`: every method on one embedded synthetic sequence in one page (the main job,
// ref/reproduce/overview.h).
#include "cli/command.h"
#include "reproduce/overview.h"

namespace dynref::cli {

void RegisterOverviewCommand(CLI::App& root, CommandList& out) {
  auto a = std::make_shared<reproduce::OverviewArgs>();
  auto seed = std::make_shared<std::string>("1");
  CLI::App* app = root.add_subcommand(
      "overview", "Run orb and every method on one synthetic sequence; one Markdown page with ATE/RPE, tracked "
                  "frames, ms/frame, rejection precision/recall, map files, trajectories and overlays");
  app->add_option("--out", a->out, "Markdown page; plots beside it (default " + a->out + ")");
  app->add_option("--work", a->work, "Working folder for the sequence and runs (default " + a->work + ")");
  app->add_option("--preset", a->preset, "Synthetic preset (default " + a->preset + ")");
  app->add_option("--frames", a->frames, "Frames (default 150)");
  app->add_option("--seed", *seed, "Synthesis seed (default 1)");
  app->add_option("--methods", a->methods, "Methods (default orb,sgdo,mgd,mgd-nd,blur,epi,semantic)")->delimiter(',');
  app->add_option("--viewer", a->viewer, "Link to a dynref view site, relative to the page (default none)");
  app->add_option("--overlay-frame", a->overlay_frame, "Frame of the overlay montage (default the middle one)");
  app->add_flag("--reuse", a->reuse, "Reuse the sequence and runs of an earlier call with identical inputs");
  app->footer("Exit 0: page written, every run finished. Exit 1: a run did not finish. Exit 2: bad input.");
  out.push_back({app, [a, seed] {
                   a->seed = ParseSeed(*seed, "--seed");
                   return reproduce::RunOverview(*a);
                 }});
}

}  // namespace dynref::cli
