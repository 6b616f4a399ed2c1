// --variant concurrent (issue 18): local mapping in its own thread. Its results vary from run to
// run, so these tests check what holds every time: the run completes with every output, the
// mapping thread mapped the keyframes, and `dynref diff --summary` measures how far it strays
// from the oracle.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "io/trajectory.h"
#include "pipeline/pipeline.h"
#include "test_support.h"

using namespace dynref;

TEST_CASE("run --variant concurrent: local mapping in its own thread, diffed against the oracle", "[cli]") {
  const std::string dir = test::ScratchDir("run_concurrent");
  const std::string seq = dir + "/seq";
  REQUIRE(test::RunDynref("synth --preset walking_xyz --frames 40 --seed 1 --detections yolo-like --out " + test::Quote(seq))
              .exit_code == 0);
  // mgd: its mgd.reprojection stage runs at on_map_update, i.e. in the mapping thread.
  const auto run = [&](const std::string& variant) {
    return test::RunDynref("run --method mgd --no-progress --trace full --variant " + variant + " --sequence " + test::Quote(seq) +
                           " --detections " + test::Quote(seq + "/detections/yolo-like") + " --out " +
                           test::Quote(dir + "/" + variant));
  };
  REQUIRE(run("oracle").exit_code == 0);
  const auto c = run("concurrent");
  INFO(c.output);
  REQUIRE(c.exit_code == 0);
  std::ifstream in(dir + "/concurrent/run.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  CHECK(j["variant"] == "concurrent");
  CHECK(j["end_state"] == "complete");
  CHECK(j["frames_tracked"].get<int>() >= 36);
  // Every keyframe, the first one included, went through the mapping thread's queue (its timing
  // summary's window is half the keyframes while fewer than 200).
  REQUIRE(j["timing"].contains("mapping_thread_per_keyframe"));
  const double window = j["timing"]["mapping_thread_per_keyframe"]["head_tail_frames"].get<double>();
  CHECK(window == std::floor(j["keyframes_created"].get<double>() / 2));
  CHECK(j["timing_clock"].get<std::string>().rfind("wall-clock", 0) == 0);
  // Still a SLAM run: the trajectory follows the ground truth.
  const AteResult ate = ComputeAte(ReadTumTrajectory(seq + "/groundtruth.txt"),
                                   ReadTumTrajectory(dir + "/concurrent/trajectory.txt"), AteOptions{});
  CHECK(ate.stats.rmse < 0.05);
  // How far it strays from the oracle.
  const auto d = test::RunDynref("diff " + test::Quote(dir + "/oracle") + " " + test::Quote(dir + "/concurrent") + " --summary");
  CHECK(d.exit_code <= 1);
  CHECK(d.output.find("summary: final pose deviation over ") != std::string::npos);
  CHECK(d.output.find("mgd.") != std::string::npos);  // probability differences of the method's stages
}

TEST_CASE("run --variant: anything but oracle or concurrent is refused", "[cli]") {
  RunOptions o;
  o.sequence = test::SourcePath("datasets/real/tum_fr1_desk_9frames");
  o.out_dir = test::ScratchDir("run_variant_bad") + "/run";
  o.variant = "fast";
  CHECK_THROWS_WITH(RunSequence(o), Catch::Contains("--variant") && Catch::Contains("oracle or concurrent"));
  CHECK(test::RunDynref("run --variant fast --sequence " + test::Quote(o.sequence) + " --out " + test::Quote(o.out_dir)).exit_code != 0);
}
