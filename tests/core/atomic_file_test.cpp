#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

#include "core/atomic_file.h"
#include "test_support.h"

static bool Exists(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0;
}

TEST_CASE("atomic_file: nothing appears under the final name until Commit") {
  const std::string dir = dynref::test::ScratchDir("atomic_file");
  const std::string path = dir + "/out.txt";
  {
    dynref::AtomicOutputFile f(path);
    f.stream() << "half";
    CHECK_FALSE(Exists(path));
  }  // destroyed without Commit: temp removed, no output
  CHECK_FALSE(Exists(path));
  CHECK_FALSE(Exists(dynref::TempPathFor(path)));
  dynref::AtomicWriteFile(path, "whole\n");
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  CHECK(s.str() == "whole\n");
}
