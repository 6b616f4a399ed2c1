// End-to-end helper of the method tests: synthesise a walking sequence with degraded detections,
// run a method on it, return the ATE RMSE of the full trajectory (header-only; the test executable
// links dynref_pipeline, dynref_synth and dynref_eval).
#pragma once
#include <catch2/catch.hpp>
#include <string>

#include "eval/trajectory_eval.h"
#include "io/trajectory.h"
#include "pipeline/pipeline.h"
#include "synth/synth.h"
#include "test_support.h"

namespace dynref::test {

struct E2eSequence {
  synth::SynthOptions synth;
  std::string detections_dir;
};

inline E2eSequence MakeE2eSequence(const std::string& dir, int frames, uint64_t seed, const std::string& detections,
                                   bool blur) {
  E2eSequence s;
  s.synth.preset = "walking_xyz";
  s.synth.frames = frames;
  s.synth.seed = seed;
  s.synth.blur = blur;
  s.synth.detections = detections;
  s.synth.out = dir + "/seq";
  synth::GenerateSequence(s.synth);
  s.detections_dir = s.synth.out + "/detections/" + detections;
  return s;
}

// Runs `method` into `out` (trace off) and returns the ATE RMSE; every frame must have a pose.
inline double RunE2eAte(const E2eSequence& s, const std::string& method, const std::string& out) {
  RunOptions o;
  o.sequence = s.synth.out;
  o.out_dir = out;
  o.method = method;
  o.detections_dir = s.detections_dir;
  o.trace_level = "off";
  o.progress = false;
  REQUIRE(RunSequence(o).exit_code == 0);
  const TumTrajectory gt = ReadTumTrajectory(s.synth.out + "/groundtruth.txt");
  const TumTrajectory est = ReadTumTrajectory(out + "/trajectory.txt");
  REQUIRE(est.poses.size() == static_cast<size_t>(s.synth.frames));
  return ComputeAte(gt, est, AteOptions{}).stats.rmse;
}

}  // namespace dynref::test
