// Loadable modules (ref/plugins/): libraries that cost a process start more than the work most
// calls do (OpenImageIO ~0.5 CPU-s, OpenCV's imgcodecs/ximgproc with GDAL ~0.2 CPU-s: about 280
// shared libraries) are linked into small modules and loaded at their first use, so `dynref
// version`, `eval`, `trace` and the unit-test processes start in ~0.05 s (issue 37).
// A module file is looked for, in order, in
//   1. $DYNREF_MODULE_DIR (environment), when set;
//   2. <exe dir>/../lib/dynref (the installed layout, like core/resources.h's share/dynref);
//   3. the build tree's lib/dynref (the build-tree binary and the test executables).
#pragma once
#include <string>

namespace dynref {

// The address of `symbol` in the module file `module_file` (e.g. "dynref_oiio_png.so"), loading
// the module at the first call (never unloaded; thread-safe). Throws std::runtime_error naming
// every path tried when the module or the symbol is missing.
void* ModuleSymbol(const std::string& module_file, const char* symbol);

}  // namespace dynref
