// `dynref synth`: synthetic dynamic RGB-D sequences with per-pixel ground truth (issue 3);
// `dynref synth-montage`: a montage PNG of synth folders with the ground truth drawn over them.
#include <cstdint>
#include <iostream>
#include <string>

#include "cli/command.h"
#include "core/error.h"
#include "core/format.h"
#include "synth/montage.h"
#include "synth/synth.h"
#include "synth/world.h"

namespace dynref::cli {

void RegisterSynthCommand(CLI::App& root, CommandList& out) {
  auto opt = std::make_shared<synth::SynthOptions>();
  auto timing = std::make_shared<bool>(false);
  auto seed = std::make_shared<std::string>(std::to_string(opt->seed));
  std::string presets;
  for (const auto& n : synth::PresetNames()) presets += (presets.empty() ? "" : ", ") + n;
  CLI::App* app = root.add_subcommand("synth", "Generate a synthetic dynamic RGB-D sequence (TUM layout + ground truth)");
  app->add_option("--preset", opt->preset, "Scene/motion preset: " + presets)->required();
  app->add_option("--frames", opt->frames,
                  "Number of frames (0 = the preset's default, ~700-1260; at most " +
                      std::to_string(synth::kMaxFrames) + ")");
  app->add_option("--width", opt->width,
                  "Image width in pixels: 0 = 640x480 (default), else a multiple of 4 in " +
                      std::to_string(synth::kMinWidth) + "..640, height 3/4 of it, intrinsics scaled "
                      "(cheap sequences for smoke tests and fuzzing)");
  app->add_option("--seed", *seed, "Seed of every random stream (textures, clothing, noise, detections); 0..2^64-1");
  app->add_flag("--blur", opt->blur, "Motion blur: average 8 sub-frame renders over a 33 ms exposure");
  app->add_flag("--low-light", opt->low_light, "Dark, low-contrast, noisier images");
  app->add_option("--detections", opt->detections,
                  "Also write detections/<mode>/: none (default), ideal, yolo-like, sparseinst-like, all");
  app->add_option("--out", opt->out, "Output folder")->required();
  app->add_flag("--timing", *timing, "Print ms/frame (render and total) to stderr");
  out.push_back({app, [opt, timing, seed] {
                   opt->seed = ParseSeed(*seed, "--seed");
                   const synth::SynthStats s = synth::GenerateSequence(*opt);
                   std::cout << "synth: wrote " << s.frames << " frames of " << opt->preset << " to " << opt->out << "\n";
                   if (*timing)
                     std::cerr << "synth: render " << FormatFixed(s.render_ms_per_frame, 1) << " ms/frame wall ("
                               << FormatFixed(s.render_cpu_ms_per_frame, 1) << " CPU), total "
                               << FormatFixed(s.total_ms_per_frame, 1) << " ms/frame wall ("
                               << FormatFixed(s.total_cpu_ms_per_frame, 1) << " CPU)\n";
                   return int{kExitOk};
                 }});

  auto dirs = std::make_shared<std::vector<std::string>>();
  auto png = std::make_shared<std::string>();
  auto mopt = std::make_shared<synth::MontageOptions>();
  CLI::App* m = root.add_subcommand("synth-montage", "Montage PNG of synth folders with ground-truth overlay");
  m->add_option("dirs", *dirs, "Sequence folders written by dynref synth (one row each)")->required();
  m->add_option("--out", *png, "Output PNG")->required();
  m->add_option("--frames-per-row", mopt->frames_per_row, "Frames per row (plus one depth tile)");
  m->add_option("--tile-width", mopt->tile_width, "Tile width in pixels");
  out.push_back({m, [dirs, png, mopt] {
                   synth::WriteMontage(*dirs, *png, *mopt);
                   std::cout << "synth-montage: wrote " << *png << "\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
