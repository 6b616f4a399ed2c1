// A dynref subcommand: its CLI11 node and the action run when it was selected on the command line.
// Each room's command file registers itself in command_list.cpp; nothing depends on cli/.
#pragma once
#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace dynref::cli {

struct Command {
  CLI::App* app = nullptr;     // leaf subcommand (e.g. "eval", or "dump" under "trace")
  std::function<int()> run;    // returns an ExitCode
};

using CommandList = std::vector<Command>;

// A seed option read as text: CLI11's conversion to uint64_t turns "-1" and values beyond
// 2^64-1 into 18446744073709551615 without a word. Only plain decimal digits that fit uint64_t
// are accepted; anything else is an InputError naming `option`.
uint64_t ParseSeed(const std::string& text, const std::string& option);
// Seeds given as a comma-separated list of seeds and inclusive ranges: "1,2,3", "1-5", "1-3,7".
std::vector<uint64_t> ParseSeedList(const std::vector<std::string>& items, const std::string& option);

// Every registrar adds its subcommand(s) under `root` and appends the leaves to `out`.
void RegisterAllCommands(CLI::App& root, CommandList& out);

}  // namespace dynref::cli
