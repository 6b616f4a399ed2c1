#include "test_support.h"

#include <catch2/catch.hpp>
#include <sys/stat.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace dynref::test {
namespace {
std::vector<std::string>& ScratchDirsMade() {
  static std::vector<std::string> dirs;
  return dirs;
}
}  // namespace

std::string ScratchDir(const std::string& name) {
  const std::string dir = std::string(DYNREF_BINARY_DIR) + "/test_scratch/" + name;
  const std::string cmd = "rm -rf '" + dir + "' && mkdir -p '" + dir + "'";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("cannot create " + dir);
  ScratchDirsMade().push_back(dir);
  return dir;
}

// A full suite leaves several GB of sequences and runs behind otherwise; CI builds two trees
// (main and sanitizer) on one disk.
void RemoveScratchDirs() {
  const char* keep = std::getenv("DYNREF_KEEP_SCRATCH");
  if (keep && std::string(keep) == "1") return;
  std::error_code ec;
  for (const std::string& dir : ScratchDirsMade()) std::filesystem::remove_all(dir, ec);
  ScratchDirsMade().clear();
}

CommandResult RunDynref(const std::string& args) { return RunShell(Quote(DynrefExe()) + " " + args); }

CommandResult RunShell(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed: " + cmd);
  CommandResult r;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

std::string WritePatched(const std::string& text, const std::string& from, const std::string& to,
                         const std::string& path) {
  std::string s = text;
  const size_t at = s.find(from);
  if (at == std::string::npos) throw std::runtime_error("WritePatched: '" + from + "' not in the text");
  s.replace(at, from.size(), to);
  return WriteText(path, s);
}

bool FileExists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

std::string ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void ExpectBadInput(const std::string& args, const std::string& fragment) {
  const CommandResult r = RunDynref(args);
  INFO(args << "\n" << r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(fragment) != std::string::npos);
}

}  // namespace dynref::test
