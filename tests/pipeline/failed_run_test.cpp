// A failed run never replaces a published run (issue 37 item 3): a usage error, a selection of
// fewer than 2 frames, a missing detection source and a bad --set value each leave the earlier
// complete run byte for byte; a failed attempt that got as far as a run folder is kept beside it
// in OUT.failed and stderr says so.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "synth/synth.h"
#include "test_support.h"

using namespace dynref;
namespace fs = std::filesystem;

TEST_CASE("failed run: a good sgdo run survives every failed rerun into the same --out (issue 37) end to end", "[cli]") {
  const std::string dir = test::ScratchDir("failed_run_keeps");
  synth::SynthOptions so;
  so.preset = "walking_xyz";
  so.frames = 8;
  so.seed = 3;
  so.detections = "yolo-like";
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  const std::string out = dir + "/run";
  const std::string base = "run --method sgdo --sequence " + test::Quote(so.out) + " --out " + test::Quote(out) +
                           " --trace off --no-progress";
  const std::string det = " --detector gt:yolo-like";
  const test::CommandResult good = test::RunDynref(base + det);
  REQUIRE(good.exit_code == 0);
  const std::string run_json = test::ReadFileBytes(out + "/run.json");
  const std::string dense = test::ReadFileBytes(out + "/dense_map.ply");
  REQUIRE_FALSE(dense.empty());

  struct Case {
    std::string args, fragment;
    bool leaves_failed_folder;
  };
  const Case cases[] = {
      {base, "needs instance masks", true},                                 // same command without --detector
      {base + det + " --frames 7-", "need at least 2", true},             // 1 frame selected
      {base + det + " --set mgd.probability.w_pro=nan", "no stage mgd.probability", false},
      {base + det + " --set sgdo.depth.lambda=nan", "--set sgdo.depth.lambda=nan: sgdo.depth.lambda:", false},
      {base + det + " --set sgdo.densemap.context_margin_m=inf", "sgdo.densemap.context_margin_m: must be finite", false},
  };
  for (const Case& c : cases) {
    INFO(c.args);
    fs::remove_all(out + ".failed");
    const test::CommandResult r = test::RunDynref(c.args);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(c.fragment) != std::string::npos);
    CHECK(test::ReadFileBytes(out + "/run.json") == run_json);
    CHECK(test::ReadFileBytes(out + "/dense_map.ply") == dense);
    CHECK(fs::exists(out + ".failed/run.json") == c.leaves_failed_folder);
    if (c.leaves_failed_folder) CHECK(r.output.find("this failed attempt (run.json, trace.dtr) is in") != std::string::npos);
  }
}

TEST_CASE("failed run: with no earlier run the failed attempt is published where asked (issue 37) end to end", "[cli]") {
  const std::string dir = test::ScratchDir("failed_run_first");
  synth::SynthOptions so;
  so.preset = "walking_xyz";
  so.frames = 3;
  so.seed = 3;
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  const std::string out = dir + "/run";
  const test::CommandResult r =
      test::RunDynref("run --sequence " + test::Quote(so.out) + " --out " + test::Quote(out) + " --frames 2-");
  CHECK(r.exit_code == 2);
  CHECK(fs::exists(out + "/run.json"));
  CHECK_FALSE(fs::exists(out + ".failed"));
}
