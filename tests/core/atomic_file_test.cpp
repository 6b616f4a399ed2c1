#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "test_support.h"


TEST_CASE("atomic_file: nothing appears under the final name until Commit") {
  const std::string dir = dynref::test::ScratchDir("atomic_file");
  const std::string path = dir + "/out.txt";
  {
    dynref::AtomicOutputFile f(path);
    f.stream() << "half";
    CHECK_FALSE(dynref::test::FileExists(path));
  }  // destroyed without Commit: temp removed, no output
  CHECK_FALSE(dynref::test::FileExists(path));
  CHECK_FALSE(dynref::test::FileExists(dynref::TempPathFor(path)));
  dynref::AtomicWriteFile(path, "whole\n");
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  CHECK(s.str() == "whole\n");
}
