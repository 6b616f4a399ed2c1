// Where dynref's read-only data (configs/, models/, reports/paper-tables/) lives at run time
// (issue 37 item 7). One rule for every caller:
//   1. DYNREF_DATA_DIR (environment), when set: that folder;
//   2. the installed layout, found relative to the executable: <exe dir>/../share/dynref
//      (`cmake --install build --prefix P` puts bin/dynref and share/dynref/ under P), used when
//      it holds configs/; a moved prefix keeps working;
//   3. the source tree the binary was built from (DYNREF_SOURCE_DIR at compile time): the
//      build-tree binary and the test executables.
// No path into the source tree is used anywhere else at run time.
#pragma once
#include <string>

namespace dynref {

// The data folder chosen by the rule above (no trailing '/'). Never throws: when nothing exists,
// the source-tree path, so that the caller's "not found" error names a real candidate.
std::string ResourceDir();
// ResourceDir() + "/" + relative, e.g. ResourcePath("configs/orb.yaml").
std::string ResourcePath(const std::string& relative);
// The folder of the running executable ("" when /proc/self/exe cannot be read).
std::string ExecutableDir();

}  // namespace dynref
