// eval/trajectory_report.h: `dynref eval`'s evaluation and report text without the CLI.
#include <catch2/catch.hpp>
#include <sstream>

#include "core/error.h"
#include "eval/trajectory_report.h"
#include "test_support.h"

using namespace dynref;

namespace {
// 11 poses over 2.5 s along x; the estimate is the ground truth shifted by 1 m (ATE 0 after SE3).
std::string ReportTrajectory(double shift) {
  std::ostringstream o;
  for (int i = 0; i <= 10; ++i) o << 1.0 + 0.25 * i << " " << 0.1 * i + shift << " 0 0 0 0 0 1\n";
  return o.str();
}
}  // namespace

TEST_CASE("eval report: options, reading, ATE/RPE and the report text and JSON") {
  const std::string d = test::ScratchDir("eval_trajectory_report");
  TrajectoryEvalOptions o;
  o.gt = test::WriteText(d + "/gt.txt", ReportTrajectory(0));
  o.est = test::WriteText(d + "/est.txt", ReportTrajectory(1));
  o.delta = 2;
  o.delta_unit = "f";
  std::ostringstream partial;
  const TrajectoryEvalReport r = EvaluateTrajectoryFiles(o, partial);
  CHECK(partial.str().empty());
  CHECK(r.ate_options.align == AlignMode::kSE3);
  CHECK(r.rpe_options.unit == DeltaUnit::kFrames);
  CHECK(r.ate.matches.size() == 11);
  CHECK(r.rpe.pairs.size() == 8);  // evaluate_rpe.py --fixed_delta: the pair ending at the last pose is dropped
  const std::string text = TrajectoryReportText(r);
  CHECK(text.rfind("dynref eval\n  ground truth   " + o.gt + "  (11 poses)\n", 0) == 0);
  CHECK(text.find("ATE (absolute trajectory error, translation), 11 pairs\n  ate [m]  rmse 0.000000") != std::string::npos);
  CHECK(text.find("), delta 2 frames, every pair") != std::string::npos);
  const std::string json = TrajectoryReportJson(r);
  CHECK(json.find("\"delta_unit\": \"f\"") != std::string::npos);
  CHECK(json.back() == '\n');
}

TEST_CASE("eval report: bad options before any file, ATE still written when RPE fails (issue 20 item 10)") {
  const std::string d = test::ScratchDir("eval_trajectory_report_bad");
  TrajectoryEvalOptions o;
  o.gt = d + "/missing.txt";
  o.est = o.gt;
  o.delta = -1;
  std::ostringstream partial;
  CHECK_THROWS_AS(EvaluateTrajectoryFiles(o, partial), InputError);  // the delta, not the file
  o.delta = 1;
  CHECK_THROWS_WITH(EvaluateTrajectoryFiles(o, partial), Catch::Contains("missing.txt"));
  o.gt = o.est = test::WriteText(d + "/gt.txt", ReportTrajectory(0));
  o.delta = 100;  // 100 s: no RPE pair in a 2.5 s clip
  CHECK_THROWS_AS(EvaluateTrajectoryFiles(o, partial), InputError);
  CHECK(partial.str().rfind("dynref eval\nATE (absolute trajectory error, translation), 11 pairs\n  ate [m]  rmse 0.000000", 0) == 0);
}
