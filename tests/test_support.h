// Helpers shared by tests: repo paths, a scratch directory, running the dynref CLI.
#pragma once
#include <string>

namespace dynref::test {

inline std::string SourcePath(const std::string& rel) { return std::string(DYNREF_SOURCE_DIR) + "/" + rel; }
inline std::string DynrefExe() { return DYNREF_EXE; }
// Fresh, empty directory under the build tree named after the test. Removed when the test
// process ends with every test passed (RemoveScratchDirs), kept after a failure and when
// DYNREF_KEEP_SCRATCH=1 is set.
std::string ScratchDir(const std::string& name);
// Removes the directories ScratchDir made in this process, unless DYNREF_KEEP_SCRATCH=1.
void RemoveScratchDirs();

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};
// Single-quoted for the shell (paths in RunDynref arguments).
inline std::string Quote(const std::string& s) { return "'" + s + "'"; }
// Runs "build/dynref <args>" through the shell, capturing output.
CommandResult RunDynref(const std::string& args);
// Runs a shell command line, capturing stdout and stderr.
CommandResult RunShell(const std::string& command);
bool FileExists(const std::string& path);
// Writes text to path (plain write: test inputs, often deliberately broken); returns path.
std::string WriteText(const std::string& path, const std::string& text);
// Whole file as bytes ("" when it cannot be read).
std::string ReadFileBytes(const std::string& path);
// Writes `text` with its first `from` replaced by `to` to path (a deliberately broken input);
// returns path. Throws when `text` has no `from`.
std::string WritePatched(const std::string& text, const std::string& from, const std::string& to,
                         const std::string& path);
// Runs dynref and expects bad-input exit code 2 with `fragment` (usually "file:line:") in the output.
void ExpectBadInput(const std::string& args, const std::string& fragment);

}  // namespace dynref::test
