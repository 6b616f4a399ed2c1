// `dynref overlay RUN --frames A-B`: off-screen overlays of a finished run (ref/render/overlay.h).
#include <iostream>
#include <limits>

#include "cli/command.h"
#include "core/error.h"
#include "core/frame_range.h"
#include "render/overlay.h"

namespace dynref::cli {

void RegisterOverlayCommand(CLI::App& root, CommandList& out) {
  struct Args {
    std::string run, frames;
    render::OverlayOptions options;
  };
  auto args = std::make_shared<Args>();
  CLI::App* app = root.add_subcommand(
      "overlay", "Render features (coloured by dynamic probability), decisions, instances, lines "
                 "and planes of a finished run onto its RGB frames (PNG, off-screen)");
  app->add_option("run", args->run, "Run directory (trace.dtr + run.json) or trace file")->required();
  app->add_option("--frames", args->frames, "Frames A, A-B or A- (0-based, inclusive; A- = every traced frame from A)")->required();
  app->add_option("--out", args->options.out_dir, "Output folder (default RUN/overlays)");
  app->add_option("--montage", args->options.montage_path, "Also tile all frames into this PNG");
  app->add_option("--montage-columns", args->options.montage_columns, "Tiles per row (>= 1, default 3)");
  app->add_flag("--gt", args->options.gt,
                "Ground-truth rings (red = GT dynamic, white = static) from SEQ/gt/");
  out.push_back({app, [args] {
                   const FrameRange range = ParseFrameRange(args->frames);
                   const int64_t first = range.first;
                   const int64_t last =
                       range.open_ended() ? std::numeric_limits<int64_t>::max() : range.last;
                   for (const std::string& p :
                        render::RenderRunOverlays(args->run, first, last, args->options))
                     std::cout << p << "\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
