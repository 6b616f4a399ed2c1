// `dynref version`: version and commit of this build.
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "core/version.h"

namespace dynref::cli {

void RegisterVersionCommand(CLI::App& root, CommandList& out) {
  CLI::App* app = root.add_subcommand("version", "Print dynref version and build commit");
  out.push_back({app, [] {
                   std::cout << "dynref " << DYNREF_VERSION << " (" << DYNREF_GIT_COMMIT << ")\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
