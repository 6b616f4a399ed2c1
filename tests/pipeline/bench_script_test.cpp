// scripts/bench-backbone.sh keeps working (it is the speed benchmark of the backbone; timings are
// only printed, never compared): a tiny run must produce one table row per sequence.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.h"

using namespace dynref::test;

TEST_CASE("bench script: per-module table for two synthetic sequences", "[cli]") {
  const std::string out = ScratchDir("bench_script");
  const CommandResult r = RunShell("DYNREF=" + Quote(DynrefExe()) + " DYNREF_BENCH_OUT=" + Quote(out) +
                                   " bash " + Quote(SourcePath("scripts/bench-backbone.sh")) + " 12");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::ifstream in(out + "/backbone_runtime.md");
  REQUIRE(in.good());
  int rows = 0;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| static_xyz-12 |", 0) == 0 || line.rfind("| walking_xyz-12 |", 0) == 0) {
      ++rows;
      CHECK(line.find("| 12 |") != std::string::npos);  // frames processed
      CHECK(line.find("nan") == std::string::npos);
    }
  }
  CHECK(rows == 2);
}
