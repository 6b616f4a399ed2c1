// Helpers shared by tests: repo paths, a scratch directory, running the dynref CLI.
#pragma once
#include <string>

namespace dynref::test {

inline std::string SourcePath(const std::string& rel) { return std::string(DYNREF_SOURCE_DIR) + "/" + rel; }
inline std::string DynrefExe() { return DYNREF_EXE; }
// Fresh, empty directory under the build tree named after the test.
std::string ScratchDir(const std::string& name);

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};
// Runs "build/dynref <args>" through the shell, capturing output.
CommandResult RunDynref(const std::string& args);

}  // namespace dynref::test
