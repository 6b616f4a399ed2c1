// The one place that lists dynref's subcommands (one line per command file).
#include "cli/command.h"

namespace dynref::cli {

void RegisterVersionCommand(CLI::App& root, CommandList& out);

void RegisterAllCommands(CLI::App& root, CommandList& out) {
  RegisterVersionCommand(root, out);
}

}  // namespace dynref::cli
