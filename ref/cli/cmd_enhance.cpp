// `dynref enhance IMAGE|SEQ --out DIR`: seed 004 Module A on files (ref/dynamic/epi/enhance_files.h).
#include <sys/stat.h>

#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "core/format.h"
#include "dynamic/epi/enhance_files.h"
#include "io/sequence.h"
#include "pipeline/method_config.h"
#include "io/image_file.h"

namespace dynref::cli {
namespace {

// Seed 004's two-scale fusion resizes the image by `down` (cv::resize rounds each side): a side
// that rounds to 0 px made OpenCV assert (issue 37: a 1x1 image). Checked before any work, on
// the image or on a sequence's first RGB frame; unreadable inputs are left to EnhanceFiles.
void RequireEnhanceableSize(const std::string& input, double down) {
  struct stat st {};
  if (::stat(input.c_str(), &st) != 0) return;
  std::string where = input;
  cv::Mat img;
  if (S_ISDIR(st.st_mode)) {
    const Sequence seq = OpenSequence(input);
    if (seq.frames.empty()) return;
    where = seq.frames.front().rgb_path;
    img = LoadRgb(seq, seq.frames.front());
  } else {
    img = dynref::ImageRead(input, cv::IMREAD_UNCHANGED);
  }
  if (img.empty() || (cvRound(img.cols * down) >= 1 && cvRound(img.rows * down) >= 1)) return;
  int min_side = 1;
  while (cvRound(min_side * down) < 1) ++min_side;
  throw InputError(where, "image is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                              ": the enhancement's two-scale step (epi.enhance down = " + FormatDouble17(down) +
                              ") needs both sides >= " + std::to_string(min_side) + " px");
}

}  // namespace

void RegisterEnhanceCommand(CLI::App& root, CommandList& out) {
  auto input = std::make_shared<std::string>();
  auto dir = std::make_shared<std::string>();
  auto config = std::make_shared<std::string>(MethodConfigPath("epi"));
  CLI::App* app = root.add_subcommand(
      "enhance", "Low-light enhancement of seed 004 (Module A) on an image or a sequence's RGB frames (PNG, grey)");
  app->add_option("input", *input, "Image file or TUM-layout sequence folder")->required();
  app->add_option("--out", *dir, "Output folder (published whole)")->required();
  app->add_option("--config", *config, "Method config whose epi.enhance parameters are used (default configs/epi.yaml)");
  out.push_back({app, [input, dir, config] {
                   const MethodConfig cfg = LoadMethodConfig(*config);
                   const StageConfig* stage = nullptr;
                   for (const StageConfig& sc : cfg.stages)
                     if (sc.name == "epi.enhance") stage = &sc;
                   if (stage == nullptr) throw InputError(*config, "has no epi.enhance stage");
                   const epi::EnhanceStageOptions options = epi::EnhanceOptionsFromParams(stage->params);
                   RequireEnhanceableSize(*input, options.params.down);
                   const epi::EnhanceFilesResult r = epi::EnhanceFiles(*input, *dir, options);
                   std::cout << "enhance: wrote " << r.images << " image(s) to " << *dir << " (alpha "
                             << FormatFixed(r.alpha, 3) << ", p " << FormatFixed(r.p, 3) << ")\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
