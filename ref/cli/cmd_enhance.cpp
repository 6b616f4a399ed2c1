// `dynref enhance IMAGE|SEQ --out DIR`: seed 004 Module A on files (ref/dynamic/epi/enhance_files.h).
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "core/format.h"
#include "dynamic/epi/enhance_files.h"
#include "pipeline/method_config.h"

namespace dynref::cli {

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
                   const epi::EnhanceFilesResult r = epi::EnhanceFiles(*input, *dir, epi::EnhanceOptionsFromParams(stage->params));
                   std::cout << "enhance: wrote " << r.images << " image(s) to " << *dir << " (alpha "
                             << FormatFixed(r.alpha, 3) << ", p " << FormatFixed(r.p, 3) << ")\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
