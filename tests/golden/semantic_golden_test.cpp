// Golden 30-frame semantic trace (issue 16): synthesise walking_xyz (30 frames, seed 1, yolo-like
// detections), run semantic mapping (golden/semantic_30f/semantic_golden.yaml = configs/semantic.yaml with 300
// features) at trace level full and diff the trace against
// golden/semantic_30f/trace.dtr with `dynref diff` (exact: no tolerance).
// Regenerate (and say in the commit why the new numbers are right):
//   DYNREF_UPDATE_GOLDEN=1 ctest -R 'golden_semantic:'
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>

#include "pipeline/pipeline.h"
#include "synth/synth.h"
#include "test_support.h"

namespace fs = std::filesystem;

TEST_CASE("semantic golden: 30-frame walking_xyz trace is unchanged") {
  const std::string dir = dynref::test::ScratchDir("semantic_golden");
  dynref::synth::SynthOptions so;
  so.preset = "walking_xyz";
  so.frames = 30;
  so.seed = 1;
  so.detections = "yolo-like";
  so.out = dir + "/seq";
  dynref::synth::GenerateSequence(so);

  dynref::RunOptions ro;
  ro.sequence = so.out;
  ro.out_dir = dir + "/run";
  ro.method = "semantic";
  ro.config_path = dynref::test::SourcePath("golden/semantic_30f/semantic_golden.yaml");
  ro.trace_level = "full";
  ro.detections_dir = so.out + "/detections/yolo-like";
  ro.progress = false;
  const dynref::RunResult r = dynref::RunSequence(ro);
  REQUIRE(r.exit_code == 0);
  CHECK(r.frames == 30);

  const std::string golden = dynref::test::SourcePath("golden/semantic_30f/trace.dtr");
  const char* update = std::getenv("DYNREF_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    fs::create_directories(fs::path(golden).parent_path());
    fs::copy_file(ro.out_dir + "/trace.dtr", golden, fs::copy_options::overwrite_existing);
    // Update mode never passes: the new golden must be committed and compared by a normal run.
    FAIL("golden updated: " << golden << "; rerun without DYNREF_UPDATE_GOLDEN to compare");
  }
  REQUIRE(fs::exists(golden));
  const dynref::test::CommandResult d = dynref::test::RunDynref("diff " + golden + " " + ro.out_dir);
  INFO(d.output);
  CHECK(d.exit_code == 0);
}
