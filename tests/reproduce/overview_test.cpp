// `dynref overview` (the main job's page): every run's end state is in its row, and the command
// exits 0 when every run finished. The summary never read run.json's end_state, so the column was
// empty and the command exited 1 on runs that had all completed.
#include <catch2/catch.hpp>
#include <string>

#include "test_support.h"

using dynref::test::Quote;
using dynref::test::ReadFileBytes;
using dynref::test::RunDynref;
using dynref::test::ScratchDir;

TEST_CASE("overview: each row states its run's end state and a page of finished runs exits 0", "[cli]") {
  const std::string d = ScratchDir("overview_end_state");
  const auto r = RunDynref("overview --preset walking_xyz --frames 10 --methods orb,mgd --work " + Quote(d + "/work") +
                           " --out " + Quote(d + "/overview.md"));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  const std::string md = ReadFileBytes(d + "/overview.md");
  CHECK(md.find("| orb | complete | ") != std::string::npos);
  CHECK(md.find("| mgd | complete | ") != std::string::npos);
}
