#include <catch2/catch.hpp>

#include <stdexcept>

#include "dynamic/sgdo/coarse.h"

using namespace dynref::sgdo;

namespace {
// instance, has_distance, distance
const std::vector<CoarseInput> kInputs = {
    {0, true, 0.2},   // 0 background static
    {0, true, 3.0},   // 1 background geometric-dynamic
    {0, false, 0},    // 2 background without pair
    {1, true, 0.3},   // 3 person 1 edge point, static
    {1, true, 5.0},   // 4 person 1 moving
    {1, true, 4.0},   // 5 person 1 moving
    {1, false, 0},    // 6 person 1 without pair
    {2, true, 0.1},   // 7 person 2 (sitting) static
    {2, true, 0.4},   // 8 person 2 static
    {2, true, 2.0},   // 9 person 2 one outlier
};

std::vector<bool> Kept(const CoarseResult& r) {
  std::vector<bool> k;
  for (const auto& d : r.decisions) k.push_back(d.keep);
  return k;
}
}  // namespace

TEST_CASE("sgdo coarse: per-point reading (spec 001 step 3e)") {
  CoarseOptions o;
  const CoarseResult r = CombineCoarse(kInputs, o);
  CHECK(Kept(r) == std::vector<bool>{true, false, true, true, false, false, false, true, true, false});
  CHECK(r.decisions[6].reason == "mask-no-pair");
  CHECK(r.decisions[1].reason == "epipolar");
  CHECK(r.decisions[2].reason == "no-pair");
}

TEST_CASE("sgdo coarse: (S) rejects every keypoint in M, (G) ignores M") {
  CoarseOptions s;
  s.mode = CoarseMode::kMaskOnly;
  CHECK(Kept(CombineCoarse(kInputs, s)) ==
        std::vector<bool>{true, true, true, false, false, false, false, false, false, false});
  CoarseOptions g;
  g.mode = CoarseMode::kEpipolarOnly;
  CHECK(Kept(CombineCoarse(kInputs, g)) ==
        std::vector<bool>{true, false, true, true, false, false, true, true, true, false});
}

TEST_CASE("sgdo coarse: instance vote (spec 001 E1 alternative)") {
  CoarseOptions o;
  o.mode = CoarseMode::kInstanceVote;
  o.vote_ratio = 0.5;
  const CoarseResult r = CombineCoarse(kInputs, o);
  // person 1: 2 of 3 paired points dynamic -> moving; person 2: 1 of 3 -> still.
  CHECK(Kept(r) == std::vector<bool>{true, false, true, false, false, false, false, true, true, true});
  REQUIRE(r.votes.size() == 2);
  CHECK(r.votes[0].instance == 1);
  CHECK(r.votes[0].moving);
  CHECK(r.votes[0].dynamic == 2);
  CHECK(r.votes[0].paired == 3);
  CHECK(!r.votes[1].moving);
  // An instance without any paired point is treated as moving (prior-dynamic class).
  const CoarseResult r2 = CombineCoarse({{3, false, 0}}, o);
  CHECK(!r2.decisions[0].keep);
}

TEST_CASE("sgdo coarse: mode names round-trip and bad options are named") {
  for (auto m : {CoarseMode::kPerPoint, CoarseMode::kInstanceVote, CoarseMode::kMaskOnly,
                 CoarseMode::kEpipolarOnly})
    CHECK(ParseCoarseMode(CoarseModeName(m)) == m);
  CHECK_THROWS_AS(ParseCoarseMode("or"), std::invalid_argument);
  CoarseOptions o;
  o.vote_ratio = 0;
  CHECK_THROWS_WITH(o.Check(), Catch::Contains("vote_ratio"));
}

TEST_CASE("sgdo coarse: why a point has no distance is kept in the decision (issue 21 defects 2, 3)") {
  CoarseOptions o;
  std::vector<CoarseInput> in(4);
  in[0].instance = 1, in[0].no_distance = "no-F";    // frame without a valid F: labelled as such
  in[1].instance = 0, in[1].no_distance = "no-F";
  in[2].instance = 1, in[2].no_distance = "pruned";  // flow pruned (border / patch SAD): not judged by D
  in[3].instance = 0, in[3].no_distance = "pruned";
  const CoarseResult r = CombineCoarse(in, o);
  CHECK(r.decisions[0].reason == "mask-no-F");
  CHECK_FALSE(r.decisions[0].keep);
  CHECK(r.decisions[1].reason == "no-F");
  CHECK(r.decisions[1].keep);
  CHECK(r.decisions[2].reason == "mask-pruned");
  CHECK(r.decisions[3].reason == "pruned");
  CHECK(r.decisions[3].keep);  // a static point with poor flow is no longer rejected as "epipolar"
  o.mode = CoarseMode::kEpipolarOnly;
  CHECK(CombineCoarse(in, o).decisions[0].reason == "no-F");
}
