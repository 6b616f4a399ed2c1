// The public figures of issue 2 on the bundled fr2_desk pair (TUM rgbd_benchmark_tools and
// evo on the same files), compared at the precision those tools print (6 decimals).
#include <catch2/catch.hpp>

#include "core/format.h"
#include "eval/trajectory_eval.h"
#include "test_support.h"

using namespace dynref;

namespace {
const std::string kGt = "datasets/real/trajectories/fr2_desk_groundtruth.txt";
const std::string kEst = "datasets/real/trajectories/fr2_desk_ORB.txt";
std::string F(double v) { return FormatFixed(v, 6); }
}  // namespace

TEST_CASE("figures: TUM evaluate_ate.py (greedy association, SE(3))") {
  const TumTrajectory gt = ReadTumTrajectory(test::SourcePath(kGt));
  const TumTrajectory est = ReadTumTrajectory(test::SourcePath(kEst));
  CHECK(gt.duplicates_dropped == 1);  // 1311868229.5760 twice in the official ground truth
  const AteResult r = ComputeAte(gt, est, {});
  CHECK(r.matches.size() == 2223);
  CHECK(F(r.stats.rmse) == "0.008144");
  CHECK(F(r.stats.mean) == "0.007514");
  CHECK(F(r.stats.median) == "0.007432");
  CHECK(F(r.stats.std) == "0.003140");
  CHECK(F(r.stats.min) == "0.000332");
  CHECK(F(r.stats.max) == "0.024329");
}

TEST_CASE("figures: TUM evaluate_rpe.py --fixed_delta --delta 1 --delta_unit s") {
  const TumTrajectory gt = ReadTumTrajectory(test::SourcePath(kGt));
  const TumTrajectory est = ReadTumTrajectory(test::SourcePath(kEst));
  const RpeResult r = ComputeRpe(gt, est, {});
  CHECK(r.pairs.size() == 1998);
  CHECK(F(r.trans_m.rmse) == "0.007161");
  CHECK(F(r.trans_m.mean) == "0.006502");
  CHECK(F(r.trans_m.median) == "0.006218");
  CHECK(F(r.trans_m.std) == "0.003001");
  CHECK(F(r.trans_m.min) == "0.000167");
  CHECK(F(r.trans_m.max) == "0.021224");
  CHECK(F(r.rot_deg.rmse) == "0.455005");
  CHECK(F(r.rot_deg.mean) == "0.401638");
  CHECK(F(r.rot_deg.median) == "0.365846");
  CHECK(F(r.rot_deg.std) == "0.213814");
  CHECK(F(r.rot_deg.min) == "0.008244");
  CHECK(F(r.rot_deg.max) == "1.732641");
}

TEST_CASE("figures: evo_ape tum GT EST -a --t_max_diff 0.02") {
  TumReadOptions all;
  all.duplicates = DuplicateStamps::kKeepAll;
  const TumTrajectory gt = ReadTumTrajectory(test::SourcePath(kGt), all);
  const TumTrajectory est = ReadTumTrajectory(test::SourcePath(kEst), all);
  AteOptions opt;
  opt.association = AssociationKind::kEvo;
  const AteResult r = ComputeAte(gt, est, opt);
  CHECK(r.matches.size() == 2225);
  CHECK(F(r.stats.rmse) == "0.008146");
  CHECK(F(r.stats.mean) == "0.007517");
  CHECK(F(r.stats.median) == "0.007437");
  CHECK(F(r.stats.std) == "0.003139");
  CHECK(F(r.stats.min) == "0.000338");
  CHECK(F(r.stats.max) == "0.024338");
  CHECK(F(r.stats.sse) == "0.147643");
}

TEST_CASE("figures: dynref eval prints them and states every choice", "[cli]") {
  const std::string args =
      "eval --gt '" + test::SourcePath(kGt) + "' --est '" + test::SourcePath(kEst) + "'";
  const auto tum = test::RunDynref(args);
  INFO(tum.output);
  REQUIRE(tum.exit_code == 0);
  for (const char* s :
       {"association    tum", "max-diff 0.02 s", "pairs used     2223 of 20956 gt / 2893 est",
        "alignment      se3", "rmse 0.008144  mean 0.007514  median 0.007432  std 0.003140  "
                              "min 0.000332  max 0.024329",
        "1998 used", "no random sub-sampling",
        "rmse 0.007161  mean 0.006502  median 0.006218  std 0.003001  min 0.000167  max 0.021224",
        "rmse 0.455005  mean 0.401638  median 0.365846  std 0.213814  min 0.008244  max 1.732641"})
    CHECK(tum.output.find(s) != std::string::npos);
  const auto evo = test::RunDynref(args + " --assoc evo");
  INFO(evo.output);
  REQUIRE(evo.exit_code == 0);
  CHECK(evo.output.find("association    evo") != std::string::npos);
  CHECK(evo.output.find("pairs used     2225") != std::string::npos);
  CHECK(evo.output.find("rmse 0.008146  mean 0.007517  median 0.007437  std 0.003139  "
                        "min 0.000338  max 0.024338  sse 0.147643") != std::string::npos);
}
