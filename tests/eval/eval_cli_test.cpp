// `dynref eval`: bad trajectories through the CLI (message naming file and line, exit code 2)
// and atomic --json.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>

#include "test_support.h"

using dynref::test::ExpectBadInput;
using dynref::test::Quote;
using dynref::test::RunDynref;
using dynref::test::WriteText;

namespace {

const std::string kTraj =
    "1.0 0 0 0 0 0 0 1\n1.03125 0.1 0 0 0 0 0 1\n1.0625 0.2 0 0 0 0 0 1\n"
    "1.09375 0.3 0.01 0 0 0 0 1\n1.125 0.4 0 0.02 0 0 0 1\n";

}  // namespace

TEST_CASE("eval cli: bad trajectories exit 2 naming file and line", "[cli]") {
  const std::string d = dynref::test::ScratchDir("eval_cli_bad");
  const std::string gt = WriteText(d + "/gt.txt", kTraj);
  auto eval = [&](const std::string& est) { return "eval --gt " + Quote(gt) + " --est " + Quote(est); };
  ExpectBadInput(eval(d + "/missing.txt"), d + "/missing.txt: file not found");
  ExpectBadInput("eval --gt " + Quote(d + "/nogt.txt") + " --est " + Quote(gt), d + "/nogt.txt: file not found");
  ExpectBadInput(eval(WriteText(d + "/malformed.txt", kTraj + "1.2 0 0 0 0 0 1\n")), d + "/malformed.txt:6: malformed line");
  ExpectBadInput(eval(WriteText(d + "/nonnum.txt", "# x\n" + kTraj + "1.2 0 0 0 0 0 0 one\n")),
            d + "/nonnum.txt:7: field qw 'one' is not a number");
  ExpectBadInput(eval(WriteText(d + "/nan.txt", "1.0 0 0 0 0 0 0 1\n1.1 0 NaN 0 0 0 0 1\n")),
            d + "/nan.txt:2: pose field ty is NaN");
  ExpectBadInput(eval(WriteText(d + "/inf.txt", "1.0 0 0 inf 0 0 0 1\n")), d + "/inf.txt:1: pose field tz is inf");
  ExpectBadInput(eval(WriteText(d + "/quat.txt", "1.0 0 0 0 0.1 0 0 1\n")), d + "/quat.txt:1: quaternion not normalised");
  ExpectBadInput(eval(WriteText(d + "/order.txt", "2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n")),
            d + "/order.txt:2: timestamps not increasing");
  ExpectBadInput("eval --gt " + Quote(WriteText(d + "/empty.txt", "# nothing\n")) + " --est " + Quote(gt),
            d + "/empty.txt: no poses");
  ExpectBadInput(eval(WriteText(d + "/far.txt", "500 0 0 0 0 0 0 1\n501 0 0 0 0 0 0 1\n")),
            d + "/far.txt: zero associated pairs");
  // A quaternion within 1e-3 of unit length is normalised and accepted.
  const auto ok = RunDynref(eval(WriteText(d + "/nearunit.txt", "1.0 0 0 0 0 0 0 1.0005\n1.03125 0.1 0 0 0 0 0 1\n"
                                                           "1.0625 0.2 0 0 0 0 0 1\n1.09375 0.3 0 0 0 0 0 0.9995\n"
                                                           "1.125 0.4 0 0 0 0 0 1\n")) +
                            " --delta 1 --delta-unit f");
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
  // Usage errors are exit 2 too.
  ExpectBadInput(eval(gt) + " --align affine", "--align");
  ExpectBadInput(eval(gt) + " --no-such-flag", "no-such-flag");
  ExpectBadInput(eval(gt) + " --max-diff -1", "--max-diff");
}

TEST_CASE("eval cli: --json is written atomically and runs are byte-identical", "[cli]") {
  const std::string d = dynref::test::ScratchDir("eval_cli_json");
  const std::string gt = dynref::test::SourcePath("datasets/real/trajectories/fr2_desk_groundtruth.txt");
  const std::string est = dynref::test::SourcePath("datasets/real/trajectories/fr2_desk_ORB.txt");
  const std::string json = d + "/eval.json";
  const std::string args = "eval --gt " + Quote(gt) + " --est " + Quote(est) + " --json " + Quote(json);
  const auto a = RunDynref(args);
  REQUIRE(a.exit_code == 0);
  const std::string first = dynref::test::ReadFileBytes(json);
  CHECK(first.find("\"pairs\": 2223") != std::string::npos);
  CHECK(first.find("\"random_subsampling\": false") != std::string::npos);
  const auto b = RunDynref(args);
  CHECK(b.output == a.output);
  CHECK(dynref::test::ReadFileBytes(json) == first);
  // A failing run leaves the previous result untouched and no temp file behind.
  const std::string bad = WriteText(d + "/bad.txt", "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n");
  ExpectBadInput("eval --gt " + Quote(gt) + " --est " + Quote(bad) + " --json " + Quote(json), "bad.txt:2:");
  CHECK(dynref::test::ReadFileBytes(json) == first);
  const auto c = RunDynref("eval --gt " + Quote(gt) + " --est " + Quote(bad) + " --json " + Quote(d + "/new.json"));
  CHECK(c.exit_code == 2);
  CHECK(!dynref::test::FileExists(d + "/new.json"));
  CHECK(std::system(("ls " + Quote(d) + " | grep -q tmp").c_str()) != 0);
}


TEST_CASE("eval cli: --offset and --save-rpe (evaluate_rpe.py --offset / --save)", "[cli]") {
  const std::string d = dynref::test::ScratchDir("eval_cli_offset");
  const std::string gt = WriteText(d + "/gt.txt", kTraj);
  // The estimate repeats the gt poses with stamps 1/32 s late; --offset -0.03125 undoes that.
  const std::string est = WriteText(d + "/est.txt",
                                    "1.03125 0 0 0 0 0 0 1\n1.0625 0.1 0 0 0 0 0 1\n"
                                    "1.09375 0.2 0 0 0 0 0 1\n1.125 0.3 0.01 0 0 0 0 1\n");
  const std::string pairs = d + "/rpe.txt";
  const auto r = RunDynref("eval --gt " + Quote(gt) + " --est " + Quote(est) +
                           " --delta 1 --delta-unit f --offset -0.03125 --save-rpe " + Quote(pairs));
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("offset -0.03125 s") != std::string::npos);
  CHECK(r.output.find("translational [m]  rmse 0.000000  mean") != std::string::npos);
  // Pairs (0,1) and (1,2): the pair ending at the last estimate is dropped as in the TUM tool.
  const std::string saved = dynref::test::ReadFileBytes(pairs);
  CHECK(saved == "1.03125 1.0625 1 1.03125 0 0\n1.0625 1.09375 1.03125 1.0625 0 0\n");
  const auto no_offset = RunDynref("eval --gt " + Quote(gt) + " --est " + Quote(est) +
                                   " --delta 1 --delta-unit f");
  REQUIRE(no_offset.exit_code == 0);
  CHECK(no_offset.output.find("offset 0 s") != std::string::npos);
  CHECK(no_offset.output.find("translational [m]  rmse 0.000000  mean") == std::string::npos);
}

TEST_CASE("eval cli: --align sim3 on a constant estimate exits 2 with a clear message", "[cli]") {
  const std::string d = dynref::test::ScratchDir("eval_cli_sim3_constant");
  const std::string gt = WriteText(d + "/gt.txt", kTraj);
  const std::string est = WriteText(d + "/const.txt", "1.0 0.5 0 0 0 0 0 1\n1.03125 0.5 0 0 0 0 0 1\n"
                                                      "1.0625 0.5 0 0 0 0 0 1\n1.09375 0.5 0 0 0 0 0 1\n"
                                                      "1.125 0.5 0 0 0 0 0 1\n");
  ExpectBadInput("eval --gt " + Quote(gt) + " --est " + Quote(est) + " --align sim3",
                 est + ": --align sim3: all 5 associated estimate positions coincide");
  const auto se3 = RunDynref("eval --gt " + Quote(gt) + " --est " + Quote(est) + " --delta 1 --delta-unit f");
  INFO(se3.output);
  CHECK(se3.exit_code == 0);
}

TEST_CASE("eval cli: a clip shorter than delta says so and still prints ATE (issue 20 item 10)", "[cli]") {
  const std::string d = dynref::test::ScratchDir("eval_cli_short_clip");
  const std::string gt = WriteText(d + "/gt.txt", kTraj);  // 5 poses over 0.125 s: stamps overlap
  const auto r = RunDynref("eval --gt " + Quote(gt) + " --est " + Quote(gt));  // default delta 1 s
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("ate [m]  rmse 0.000000") != std::string::npos);  // ATE printed first
  CHECK(r.output.find("are delta = 1 s apart (the estimate has 5 poses over 0.125 s)") != std::string::npos);
  CHECK(r.output.find("do the stamps overlap") == std::string::npos);  // the wrong hint is gone
}

TEST_CASE("eval cli: a frame delta must be a whole number, a seconds delta must not pair a pose with itself (issue 37)", "[cli]") {
  const std::string d = dynref::test::ScratchDir("eval_cli_delta_range");
  const std::string gt = WriteText(d + "/gt.txt", kTraj);  // 5 poses, 31.25 ms apart
  const std::string base = "eval --gt " + Quote(gt) + " --est " + Quote(gt);
  // 0.5 frames paired every pose with itself and reported "delta 0.5 frames".
  ExpectBadInput(base + " --delta 0.5 --delta-unit f", "--delta: with --delta-unit f must be a whole number of frames >= 1, got 0.5");
  ExpectBadInput(base + " --delta 1.5 --delta-unit f", "whole number of frames");
  ExpectBadInput(base + " --delta 0 --delta-unit f", "--delta: must be a finite number > 0");
  ExpectBadInput(base + " --delta -2 --delta-unit f", "--delta: must be a finite number > 0");
  // 10 ms is less than half the 31.25 ms interval: every pose's partner would be itself.
  ExpectBadInput(base + " --delta 0.01", "--delta: delta = 0.01 s pairs estimate pose 0 (stamp 1) with itself");
  ExpectBadInput(base + " --delta 0.01 --rpe-mode interp", "with itself");
  ExpectBadInput(base + " --delta 0 --delta-unit s", "--delta: must be a finite number > 0");
  // Whole frames and a seconds delta of one interval are fine.
  const auto ok = RunDynref(base + " --delta 1 --delta-unit f");
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
  CHECK(ok.output.find("delta 1 frames") != std::string::npos);
  CHECK(RunDynref(base + " --delta 0.03125").exit_code == 0);
}
