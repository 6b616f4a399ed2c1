// `dynref view RUN... --out DIR`: a static site to browse runs and one feature's history
// (ref/view/README.md).
#include <unistd.h>

#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "core/format.h"
#include "view/site_writer.h"

namespace dynref::cli {

void RegisterViewCommand(CLI::App& root, CommandList& out) {
  auto options = std::make_shared<view::ViewOptions>();
  CLI::App* app = root.add_subcommand(
      "view", "Write a static site (open DIR/index.html in a browser, no server) to browse runs: frame slider "
              "with overlays, click a feature to see its whole history across frames");
  app->add_option("runs", options->runs, "Run folders (with trace.dtr; the first is the oracle when several)")
      ->required();
  app->add_option("--out", options->out_dir, "Site folder (replaced when written by dynref view before)")->required();
  app->add_flag("!--no-overlays", options->overlays, "Do not render the frames' overlays");
  app->add_option("--jpeg-quality", options->jpeg_quality, "Overlay JPEG quality 1..100 (default 60)");
  app->add_option("--image-scale", options->image_scale, "Overlay JPEG size relative to the frame, 0.1..1 (default 0.5)");
  app->add_option("--digits", options->digits,
                  "Significant digits of the numbers the page shows, 1..17 (default 6; 17 = exact, a larger site)");
  app->add_option("--chunk-frames", options->chunk_frames,
                  "Frames per data file, 1..1000 (default 30: one LZMA stream each, smaller than fewer; the page decodes "
                  "a whole file to show one of its frames)");
  app->add_option("--threads", options->threads,
                  "Threads compressing the data files (LZMA is most of the time; the site's bytes are the same for "
                  "every N; default 1)");
  app->footer("Exit 0: site written. Exit 2: bad input (a run without trace, an existing folder not written by dynref view).");
  out.push_back({app, [options] {
                   options->progress = ::isatty(STDERR_FILENO) != 0;
                   const view::ViewResult r = view::WriteSite(*options);
                   std::cout << "view: " << options->out_dir << "/index.html (" << r.frames << " frames, " << r.images
                             << " overlays, " << FormatFixed(r.bytes / 1048576.0, 1) << " MiB)\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
