// dynref: deterministic reference implementation and validator for dynamic-scene RGB-D SLAM.
#include <opencv2/core.hpp>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>

#include "cli/command.h"
#include "core/error.h"

namespace {

// CLI11 reports an unknown word where a subcommand is required as "A subcommand is required".
// Walks the command words (before the first option) and, at the first one that is not a
// subcommand of the node reached so far, prints "unknown command" with the valid names (and,
// when the words end where a subcommand is required, the valid names too). False: leave the
// error to CLI11.
bool ReportUnknownSubcommand(CLI::App& root, int argc, char** argv) {
  CLI::App* node = &root;
  std::string path = "dynref";
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') return false;
    const auto subs = node->get_subcommands([](CLI::App*) { return true; });
    if (subs.empty()) return false;  // a leaf: positional arguments follow
    CLI::App* next = nullptr;
    std::string valid;
    for (CLI::App* s : subs) {
      if (s->check_name(word)) next = s;
      valid += (valid.empty() ? "" : ", ") + s->get_name();
    }
    if (!next) {
      std::cerr << "dynref: error: unknown command '" << word << "' for '" << path << "' (valid: " << valid
                << "; see " << path << " --help)\n";
      return true;
    }
    node = next;
    path += " " + next->get_name();
  }
  // Words ran out at a node that needs a subcommand: say which ones exist.
  const auto subs = node->get_subcommands([](CLI::App*) { return true; });
  if (subs.empty() || node->get_require_subcommand_min() == 0) return false;
  std::string valid;
  for (CLI::App* s : subs) valid += (valid.empty() ? "" : ", ") + s->get_name();
  std::cerr << "dynref: error: a subcommand is required for '" << path << "' (valid: " << valid << "; see "
            << path << " --help)\n";
  return true;
}

}  // namespace

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
    if (e.get_exit_code() != 0 && ReportUnknownSubcommand(root, argc, argv)) return dynref::kExitBadInput;
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
  } catch (const std::filesystem::filesystem_error& e) {
    // Not the library's "filesystem error: ..." text: the path and the system's reason.
    std::cerr << "dynref: error: " << (e.path1().empty() ? std::string("<filesystem>") : e.path1().string())
              << ": " << e.code().message() << "\n";
    return dynref::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "dynref: error: " << e.what() << "\n";
    return dynref::kExitBadInput;
  }
}
