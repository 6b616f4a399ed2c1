// dynref: deterministic reference implementation and validator for dynamic-scene RGB-D SLAM.
#include <opencv2/core.hpp>
#include <exception>
#include <iostream>

#include "cli/command.h"
#include "core/error.h"

int main(int argc, char** argv) {
  cv::setNumThreads(0);  // determinism: OpenCV runs single-threaded everywhere
  CLI::App root{"dynref: deterministic reference implementation and validator for dynamic-scene "
                "RGB-D SLAM"};
  root.require_subcommand(1);
  dynref::cli::CommandList commands;
  dynref::cli::RegisterAllCommands(root, commands);
  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = root.exit(e);  // prints help or the parse error
    return code == 0 ? dynref::kExitOk : dynref::kExitBadInput;
  }
  try {
    for (const auto& cmd : commands)
      if (cmd.app->parsed()) return cmd.run();
    std::cerr << "dynref: no command selected (see dynref --help)\n";
    return dynref::kExitBadInput;
  } catch (const dynref::InputError& e) {
    std::cerr << "dynref: error: " << e.what() << "\n";
    return dynref::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "dynref: error: " << e.what() << "\n";
    return dynref::kExitBadInput;
  }
}
