// The one place that lists dynref's subcommands (one line per command file).
#include "cli/command.h"

namespace dynref::cli {

void RegisterVersionCommand(CLI::App& root, CommandList& out);
void RegisterEvalCommand(CLI::App& root, CommandList& out);
void RegisterInfoCommand(CLI::App& root, CommandList& out);
void RegisterDetectCommand(CLI::App& root, CommandList& out);
void RegisterTraceCommand(CLI::App& root, CommandList& out);
void RegisterDiffCommand(CLI::App& root, CommandList& out);
void RegisterOverlayCommand(CLI::App& root, CommandList& out);
void RegisterSynthCommand(CLI::App& root, CommandList& out);

void RegisterRunCommand(CLI::App& root, CommandList& out);
void RegisterReproduceCommand(CLI::App& root, CommandList& out);

void RegisterAllCommands(CLI::App& root, CommandList& out) {
  RegisterVersionCommand(root, out);
  RegisterEvalCommand(root, out);
  RegisterInfoCommand(root, out);
  RegisterDetectCommand(root, out);
  RegisterTraceCommand(root, out);
  RegisterDiffCommand(root, out);
  RegisterOverlayCommand(root, out);
  RegisterSynthCommand(root, out);
  RegisterRunCommand(root, out);
  RegisterReproduceCommand(root, out);
}

}  // namespace dynref::cli
