// The golden run of a method (issues 6, 14, 15, 16): synthesise walking_xyz (30 frames, seed 1,
// yolo-like detections unless told otherwise), run the method with golden/<name>/<config> at
// trace level full and diff the trace against golden/<name>/trace.dtr with `dynref diff` (exact: no tolerance);
// then `dynref trace verify` must recompute every record of the golden (issue 32), and the run's
// trajectory.txt must equal golden/<name>/trajectory.txt byte for byte (issue 38: the trace's pose
// records alone never checked the file users evaluate).
// Regenerate (and say in the commit why the new numbers are right):
//   DYNREF_UPDATE_GOLDEN=1 ctest -R 'golden_<method>:'
#pragma once
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "pipeline/pipeline.h"
#include "synth/synth.h"
#include "test_support.h"

namespace dynref::test {

// blur / detections: seed 003's golden renders motion blur and uses sparseinst-like masks;
// low_light: seed 004's renders dark frames.
inline void CheckMethodGolden(const std::string& method, const std::string& golden_dir, const std::string& config,
                              bool blur = false, const std::string& detections = "yolo-like",
                              bool low_light = false) {
  namespace fs = std::filesystem;
  const std::string dir = ScratchDir(method + "_golden");
  synth::SynthOptions so;
  so.preset = "walking_xyz";
  so.frames = 30;
  so.seed = 1;
  so.detections = detections;
  so.blur = blur;
  so.low_light = low_light;  // seed 004's golden: dark, low-contrast frames
  so.out = dir + "/seq";
  synth::GenerateSequence(so);

  RunOptions ro;
  ro.sequence = so.out;
  ro.out_dir = dir + "/run";
  ro.method = method;
  ro.config_path = SourcePath(golden_dir + "/" + config);
  ro.trace_level = "full";
  ro.detections_dir = so.out + "/detections/" + detections;
  ro.progress = false;
  const RunResult r = RunSequence(ro);
  REQUIRE(r.exit_code == 0);
  CHECK(r.frames == 30);

  const std::string golden = SourcePath(golden_dir + "/trace.dtr");
  const std::string golden_trajectory = SourcePath(golden_dir + "/trajectory.txt");
  const char* update = std::getenv("DYNREF_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    fs::create_directories(fs::path(golden).parent_path());
    fs::copy_file(ro.out_dir + "/trace.dtr", golden, fs::copy_options::overwrite_existing);
    fs::copy_file(ro.out_dir + "/trajectory.txt", golden_trajectory, fs::copy_options::overwrite_existing);
    // Update mode never passes: the new golden must be committed and compared by a normal run.
    FAIL("golden updated: " << golden << "; rerun without DYNREF_UPDATE_GOLDEN to compare");
  }
  REQUIRE(fs::exists(golden));
  const CommandResult d = RunDynref("diff " + golden + " " + ro.out_dir);
  INFO(d.output);
  CHECK(d.exit_code == 0);
  REQUIRE(fs::exists(golden_trajectory));
  CHECK(ReadFileBytes(ro.out_dir + "/trajectory.txt") == ReadFileBytes(golden_trajectory));
  // Issue 32: the golden proves itself: every PROB, DECISION and RESIDUAL record recomputed.
  const CommandResult v = RunDynref("trace verify " + golden);
  INFO(v.output);
  CHECK(v.exit_code == 0);
}

}  // namespace dynref::test
