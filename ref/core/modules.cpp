#include "core/modules.h"

#include <dlfcn.h>

#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "core/resources.h"

namespace dynref {
namespace {

std::vector<std::string> ModuleDirs() {
  std::vector<std::string> dirs;
  const char* env = std::getenv("DYNREF_MODULE_DIR");
  if (env && *env) dirs.push_back(env);
  const std::string exe_dir = ExecutableDir();
  if (!exe_dir.empty()) dirs.push_back(exe_dir + "/../lib/dynref");
  dirs.push_back(DYNREF_MODULE_BUILD_DIR);
  return dirs;
}

void* LoadModule(const std::string& module_file, const char* symbol) {
  std::string tried;
  for (const std::string& dir : ModuleDirs()) {
    const std::string path = dir + "/" + module_file;
    // RTLD_GLOBAL: the module's libraries join the global scope, where the dynref executable's
    // dlsym(RTLD_NEXT, ...) finds libpng and libjpeg behind its interposed handlers (cli/main.cpp).
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (!handle) {
      tried += "\n  " + path + ": " + ::dlerror();
      continue;
    }
    if (void* address = ::dlsym(handle, symbol)) return address;
    tried += "\n  " + path + ": no symbol " + symbol;
  }
  throw std::runtime_error("cannot load the module " + module_file + "; looked in:" + tried);
}

}  // namespace

void* ModuleSymbol(const std::string& module_file, const char* symbol) {
  static std::mutex mutex;
  static std::map<std::string, void*> loaded;  // "file symbol" -> address
  const std::lock_guard<std::mutex> lock(mutex);
  const std::string key = module_file + " " + symbol;
  const auto it = loaded.find(key);
  if (it != loaded.end()) return it->second;
  void* address = LoadModule(module_file, symbol);
  loaded.emplace(key, address);
  return address;
}

}  // namespace dynref
