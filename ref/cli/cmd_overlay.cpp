// `dynref overlay RUN --frames A-B`: off-screen overlays of a finished run (ref/render/overlay.h).
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "render/overlay.h"

namespace dynref::cli {

// "A-B" or "A" -> [first, last].
static void ParseFrameRange(const std::string& text, int64_t* first, int64_t* last) {
  try {
    const size_t dash = text.find('-', 1);
    size_t used = 0;
    *first = std::stoll(text.substr(0, dash), &used);
    if (used != (dash == std::string::npos ? text.size() : dash)) throw std::invalid_argument("x");
    *last = *first;
    if (dash != std::string::npos) {
      *last = std::stoll(text.substr(dash + 1), &used);
      if (used != text.size() - dash - 1) throw std::invalid_argument("x");
    }
  } catch (const std::logic_error&) {
    throw InputError("--frames", "expected A-B or A, got '" + text + "'");
  }
  if (*first < 0 || *last < *first) throw InputError("--frames", "bad range '" + text + "'");
}

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
  app->add_option("--frames", args->frames, "Frame range A-B (inclusive) or one frame A")->required();
  app->add_option("--out", args->options.out_dir, "Output folder (default RUN/overlays)");
  app->add_option("--montage", args->options.montage_path, "Also tile all frames into this PNG");
  app->add_option("--montage-columns", args->options.montage_columns, "Tiles per row (default 3)");
  app->add_flag("--gt", args->options.gt,
                "Ground-truth rings (red = GT dynamic, white = static) from SEQ/gt/");
  out.push_back({app, [args] {
                   int64_t first = 0, last = 0;
                   ParseFrameRange(args->frames, &first, &last);
                   for (const std::string& p :
                        render::RenderRunOverlays(args->run, first, last, args->options))
                     std::cout << p << "\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
