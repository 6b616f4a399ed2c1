// Runs in one process are independent (issue 12): orb and sgdo run in one process in both
// orders give the same traces, trajectories and dense maps as each run in its own process
// (`dynref run`). Before the per-run Session, sgdo's stages shared one process-wide blackboard.
#include <catch2/catch.hpp>
#include <string>

#include "pipeline/pipeline.h"
#include "synth/synth.h"
#include "test_support.h"

using namespace dynref;

namespace {

struct Seq {
  std::string dir;
};

const Seq& Sequence() {
  static const Seq s = [] {
    const std::string dir = test::ScratchDir("two_methods_seq");
    synth::SynthOptions so;
    so.preset = "walking_xyz";
    so.frames = 20;
    so.seed = 4;
    so.detections = "yolo-like";
    so.out = dir + "/seq";
    synth::GenerateSequence(so);
    return Seq{so.out};
  }();
  return s;
}

void RunInProcess(const std::string& method, const std::string& out) {
  RunOptions o;
  o.sequence = Sequence().dir;
  o.out_dir = out;
  o.method = method;
  o.trace_level = "full";
  o.detections_dir = Sequence().dir + "/detections/yolo-like";
  o.progress = false;
  REQUIRE(RunSequence(o).exit_code == 0);
}

void RunOwnProcess(const std::string& method, const std::string& out) {
  const test::CommandResult r = test::RunDynref("run --method " + method + " --sequence " + test::Quote(Sequence().dir) +
                                                " --out " + test::Quote(out) + " --trace full --detections " +
                                                test::Quote(Sequence().dir + "/detections/yolo-like"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
}

void CheckSame(const std::string& a, const std::string& b, bool dense) {
  INFO(a << " vs " << b);
  CHECK(test::ReadFileBytes(a + "/trace.dtr") == test::ReadFileBytes(b + "/trace.dtr"));
  CHECK(test::ReadFileBytes(a + "/trajectory.txt") == test::ReadFileBytes(b + "/trajectory.txt"));
  if (dense) {
    REQUIRE(test::FileExists(a + "/dense_map.ply"));
    CHECK(test::ReadFileBytes(a + "/dense_map.ply") == test::ReadFileBytes(b + "/dense_map.ply"));
  }
}

}  // namespace

TEST_CASE("two methods in one process, in both orders, equal separate processes", "[cli]") {
  const std::string dir = test::ScratchDir("two_methods");
  RunOwnProcess("orb", dir + "/solo_orb");
  RunOwnProcess("sgdo", dir + "/solo_sgdo");
  RunInProcess("orb", dir + "/a_orb");
  RunInProcess("sgdo", dir + "/a_sgdo");
  RunInProcess("sgdo", dir + "/b_sgdo");
  RunInProcess("orb", dir + "/b_orb");
  RunInProcess("sgdo", dir + "/c_sgdo");  // a second sgdo run right after another one
  for (const char* run : {"a_orb", "b_orb"}) CheckSame(dir + "/solo_orb", dir + "/" + run, false);
  for (const char* run : {"a_sgdo", "b_sgdo", "c_sgdo"}) CheckSame(dir + "/solo_sgdo", dir + "/" + run, true);
}
