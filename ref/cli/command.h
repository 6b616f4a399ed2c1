// A dynref subcommand: its CLI11 node and the action run when it was selected on the command line.
// Each room's command file registers itself in command_list.cpp; nothing depends on cli/.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace dynref::cli {

struct Command {
  CLI::App* app = nullptr;     // leaf subcommand (e.g. "eval", or "dump" under "trace")
  std::function<int()> run;    // returns an ExitCode
};

using CommandList = std::vector<Command>;

// Every registrar adds its subcommand(s) under `root` and appends the leaves to `out`.
void RegisterAllCommands(CLI::App& root, CommandList& out);

}  // namespace dynref::cli
