// The feature plug-in end to end (issue 17, Module B): SIFT + MNN2 (configs/epi_B.yaml) tracks a
// static room, twice with the same bytes, every MNN2 match traced; a SuperPoint-style ONNX model
// the test builds (tests/tiny_onnx_model.h) runs through the same backbone.
#include <catch2/catch.hpp>

#include <fstream>

#include "eval/trajectory_eval.h"
#include "io/trajectory.h"
#include "pipeline/pipeline.h"
#include "synth/synth.h"
#include "test_support.h"
#include "tiny_onnx_model.h"

using namespace dynref;

namespace {

// Each test case synthesises its own copy: CTest runs them side by side.
std::string StaticRoom(const std::string& name, int frames) {
  const std::string dir = test::ScratchDir("plugin_seq_" + name);
  synth::SynthOptions so;
  so.preset = "static_xyz";
  so.frames = frames;
  so.seed = 2;
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  return so.out;
}

double Ate(const std::string& seq, const std::string& run) {
  return ComputeAte(ReadTumTrajectory(seq + "/groundtruth.txt"), ReadTumTrajectory(run + "/trajectory.txt"), AteOptions{})
      .stats.rmse;
}

}  // namespace

TEST_CASE("feature plugin: SIFT + MNN2 tracks a static room within 1 cm, twice the same bytes, matches traced", "[cli]") {
  const std::string seq = StaticRoom("sift", 40);
  std::string dump[2];
  for (int k = 0; k < 2; ++k) {
    RunOptions o;
    o.sequence = seq;
    o.out_dir = test::ScratchDir("plugin_sift_" + std::to_string(k));
    o.method = "epi_B";
    o.trace_level = "full";
    o.progress = false;
    const RunResult r = RunSequence(o);
    REQUIRE(r.exit_code == 0);
    CHECK(r.tracked == 40);
    const double ate = Ate(seq, o.out_dir);
    INFO("ATE " << ate);
    CHECK(ate < 0.01);
    const auto d = test::RunDynref("trace dump " + o.out_dir + "/trace.dtr");
    REQUIRE(d.exit_code == 0);
    dump[k] = d.output;
  }
  CHECK(dump[0] == dump[1]);
  // Keyframe-to-frame and triangulation matches with their distances and ratio.
  CHECK(dump[0].find("match.mnn2.reference,") != std::string::npos);
  CHECK(dump[0].find("match.mnn2.triangulation,") != std::string::npos);
  CHECK(dump[0].find("in.ratio") != std::string::npos);
}

TEST_CASE("feature plugin: a self-built ONNX SuperPoint runs through tracking and mapping") {
  const std::string seq = StaticRoom("onnx", 40);
  const std::string dir = test::ScratchDir("plugin_onnx");
  test::WriteTinySuperPoint(dir + "/tiny.onnx");  // 640 x 480 input, 32-float descriptors
  const std::string cfg = dir + "/onnx.yaml";
  std::ofstream(cfg) << "method: orb\nbackbone:\n"
                        "  features: {value: onnx, source: test}\n"
                        "  onnx_model: {value: tiny.onnx, source: test (relative to this file)}\n"
                        "  mnn2_matching: {value: true, source: test}\n"
                        "  min_init_points: {value: 100, source: test}\n"
                        "stages: []\n";
  RunOptions o;
  o.sequence = seq;
  o.out_dir = dir + "/run";
  o.config_path = cfg;
  o.progress = false;
  const RunResult r = RunSequence(o);
  INFO(r.end_state);
  REQUIRE(r.exit_code == 0);
  CHECK(r.frames == 40);
  CHECK(r.tracked >= 30);
  WARN("tiny ONNX model: tracked " << r.tracked << " of 40, ATE " << Ate(seq, o.out_dir) << " m");
}
