// Golden 30-frame `--method orb` run (issue 5): synthesise static_xyz (30 frames, seed 1), run
// the backbone at trace level frames and compare with golden/orb_30f: `dynref diff` of the
// trace (exact) and the trajectory byte for byte. The sequence is generated, not stored.
// Regenerate (and say in the commit why the new numbers are right):
//   DYNREF_UPDATE_GOLDEN=1 ctest -R 'golden_orb:'
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "pipeline/pipeline.h"
#include "synth/synth.h"
#include "test_support.h"

namespace fs = std::filesystem;

TEST_CASE("orb golden: 30-frame static_xyz run is unchanged", "[cli][golden]") {
  const std::string dir = dynref::test::ScratchDir("orb_golden");
  dynref::synth::SynthOptions so;
  so.preset = "static_xyz";
  so.frames = 30;
  so.seed = 1;
  so.out = dir + "/seq";
  dynref::synth::GenerateSequence(so);

  dynref::RunOptions ro;
  ro.sequence = so.out;
  ro.out_dir = dir + "/run";
  ro.method = "orb";
  ro.trace_level = "frames";
  ro.progress = false;
  const dynref::RunResult r = dynref::RunSequence(ro);
  REQUIRE(r.exit_code == 0);
  CHECK(r.frames == 30);
  CHECK(r.tracked == 30);

  const std::string golden = dynref::test::SourcePath("golden/orb_30f");
  const char* update = std::getenv("DYNREF_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    fs::create_directories(golden);
    for (const char* f : {"trace.dtr", "trajectory.txt"})
      fs::copy_file(ro.out_dir + "/" + f, golden + "/" + f, fs::copy_options::overwrite_existing);
    // Update mode never passes: the new golden must be committed and compared by a normal run.
    FAIL("golden updated: " << golden << "; rerun without DYNREF_UPDATE_GOLDEN to compare");
  }
  REQUIRE(fs::exists(golden + "/trace.dtr"));
  REQUIRE(fs::exists(golden + "/trajectory.txt"));
  const dynref::test::CommandResult d =
      dynref::test::RunDynref("diff " + golden + "/trace.dtr " + ro.out_dir + "/trace.dtr");
  INFO(d.output);
  CHECK(d.exit_code == 0);
  CHECK(dynref::test::ReadFileBytes(golden + "/trajectory.txt") == dynref::test::ReadFileBytes(ro.out_dir + "/trajectory.txt"));
}
