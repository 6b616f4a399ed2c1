// `dynref run`: the ORB-SLAM2-equivalent backbone with a method's stages (ref/pipeline).
// Exit codes: 0 the run completed (end_state "complete" or "lost-at-end"); 2 bad input or usage
// (unknown method/config error, unreadable sequence, fewer than 2 frames, an unreadable frame
// mid-run, never initialised). Outputs written before a mid-run error stay complete and
// run.json/trace record the end state.
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "pipeline/method_config.h"
#include "pipeline/pipeline.h"

namespace dynref::cli {

void RegisterRunCommand(CLI::App& root, CommandList& out) {
  CLI::App* app = root.add_subcommand("run", "Run the SLAM backbone (and a dynamic method) on a sequence");
  auto opts = std::make_shared<RunOptions>();
  auto frames = std::make_shared<std::string>();
  auto sets = std::make_shared<std::vector<std::string>>();
  app->add_option("--sequence", opts->sequence, "TUM-layout sequence folder")->required();
  app->add_option("--out", opts->out_dir, "output folder (created)")->required();
  app->add_option("--method", opts->method, "method name: configs/<method>.yaml (default orb)");
  app->add_option("--config", opts->config_path, "method config file (overrides --method lookup)");
  app->add_option("--trace", opts->trace_level, "trace level: off | frames | full (default frames)");
  app->add_option("--detections", opts->detections_dir, "dynref-detections folder for the method stages");
  app->add_option("--detector", opts->detector, "detection source spec (see dynref detect), e.g. gt:yolo-like");
  app->add_option("--detector-temporal-gap", opts->detector_temporal.max_gap,
                  "carry a person the --detector missed up to N frames along its track, as dynref detect "
                  "--temporal-gap N does (0 = off, default; ref/detect/temporal_links.h)");
  app->add_option("--detector-temporal-iou", opts->detector_temporal.iou_link,
                  "box IoU linking a detection to a track (default 0.3)");
  app->add_option("--camera", opts->camera, "camera preset or ORB-SLAM2 YAML (default: auto)");
  CLI::Option* frames_opt = app->add_option("--frames", *frames, "frames A, A-B or A- (0-based, inclusive; A- = to the end)");
  app->add_option("--set", *sets,
                  "STAGE.KEY=VALUE: change one stage parameter of the config for this run (repeatable, applied "
                  "together), e.g. sgdo.depth.eta=0.05, a list sgdo.mask.dynamic_classes=[person,dog], or a backbone "
                  "key, e.g. backbone.min_init_points=100 (paths relative to the working directory); recorded in "
                  "run.json with source 'dynref run --set'");
  app->add_flag("--overlays", opts->overlays, "render RUN/overlays/overlay_<frame>.png after the run");
  app->add_option("--variant", opts->variant,
                  "oracle (default: single thread, bit-for-bit reproducible) or concurrent (local mapping in its own "
                  "thread as in ORB-SLAM2: results vary from run to run; compare with dynref diff ORACLE RUN --summary)")
      ->check(CLI::IsMember({"oracle", "concurrent"}));
  app->add_option("--threads", opts->threads,
                  "threads for the work that stays bit-identical (ORB extraction, lines and planes, Lucas-Kanade, "
                  "per-feature probabilities, image enhancement, dense back-projection; reports/threads_bench.md); results and "
                  "traces are the same for every N; with N > 1 run.json timings are wall-clock ms (default 1)");
  app->add_flag("!--no-progress", opts->progress, "no progress line on stderr");
  out.push_back({app, [opts, frames, frames_opt, sets] {
                   // --frames here; everything else in RunOptions::Check before the run opens anything.
                   if (frames_opt->count()) {
                     if (frames->empty())
                       throw InputError("--frames", "empty value (give A, A-B or A-; omit --frames for all frames)");
                     opts->frames = ParseFrameRange(*frames);
                   }
                   if (!sets->empty()) {
                     // One batch (order-free), checked when the run builds its components.
                     auto cfg = std::make_shared<MethodConfig>(LoadMethodConfig(
                         opts->config_path.empty() ? MethodConfigPath(opts->method) : opts->config_path));
                     cfg->ApplySets(*sets, "dynref run --set");
                     opts->config = cfg;
                   }
                   const RunResult r = RunSequence(*opts);
                   std::cout << "dynref run: " << r.frames << " frames, " << r.tracked << " tracked, " << r.lost
                             << " lost, " << r.keyframes << " keyframes; end state: " << r.end_state
                             << (r.detections_summary.empty() ? "" : "; detections: " + r.detections_summary) << "\n";
                   return r.exit_code;
                 }});
}

}  // namespace dynref::cli
