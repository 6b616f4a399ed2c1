#include "core/resources.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace dynref {
namespace {

bool IsDirectory(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

std::string ExecutableDir() {
  std::vector<char> buf(4096);
  const ssize_t n = ::readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n <= 0) return "";
  const std::string exe(buf.data(), static_cast<size_t>(n));
  const size_t slash = exe.rfind('/');
  return slash == std::string::npos ? "" : exe.substr(0, slash);
}

std::string ResourceDir() {
  const char* env = std::getenv("DYNREF_DATA_DIR");
  if (env && *env) return env;
  const std::string exe_dir = ExecutableDir();
  if (!exe_dir.empty()) {
    const std::string installed = exe_dir + "/../share/dynref";
    if (IsDirectory(installed + "/configs")) return installed;
  }
  return DYNREF_SOURCE_DIR;
}

std::string ResourcePath(const std::string& relative) { return ResourceDir() + "/" + relative; }

}  // namespace dynref
