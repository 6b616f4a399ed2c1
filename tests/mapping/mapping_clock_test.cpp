// The virtual local-mapping clock (issue 18): busy time from problem size only, ORB-SLAM2's
// queue rule, and "disabled" = idle at every frame.
#include <catch2/catch.hpp>

#include "core/error.h"
#include "mapping/mapping_clock.h"

using dynref::mapping::LocalMapperStats;
using dynref::mapping::MappingClock;
using dynref::mapping::MappingClockOptions;

namespace {
LocalMapperStats WithObservations(int n) {
  LocalMapperStats s;
  s.ba_observations = n;
  return s;
}
}  // namespace

TEST_CASE("mapping clock: a keyframe keeps mapping busy for its virtual cost in sequence time") {
  MappingClockOptions o;
  o.ms_per_keyframe = 10;
  o.ms_per_ba_observation = 0.01;  // 9000 observations: 10 + 90 = 100 ms
  MappingClock clock(o);
  CHECK(clock.LoadAt(0.0).idle);
  CHECK(clock.Charge(0.0, WithObservations(9000)) == Approx(100.0));
  CHECK_FALSE(clock.LoadAt(0.033).idle);
  CHECK_FALSE(clock.LoadAt(0.099).idle);
  CHECK(clock.LoadAt(0.100).idle);
  CHECK(clock.LoadAt(0.100).queued == 0);
}

TEST_CASE("mapping clock: keyframes inserted while busy wait in a queue, processed one at a time") {
  MappingClockOptions o;
  o.ms_per_keyframe = 100;
  o.ms_per_ba_observation = 0;
  MappingClock clock(o);
  clock.Charge(0.0, {});  // busy until 0.1
  clock.Charge(0.02, {});  // starts at 0.1, busy until 0.2
  clock.Charge(0.04, {});  // starts at 0.2, busy until 0.3
  auto load = clock.LoadAt(0.05);
  CHECK_FALSE(load.idle);
  CHECK(load.queued == 2);
  CHECK(clock.LoadAt(0.15).queued == 1);
  CHECK(clock.LoadAt(0.25).queued == 0);
  CHECK_FALSE(clock.LoadAt(0.25).idle);
  CHECK(clock.LoadAt(0.3001).idle);  // 0.1 + 0.1 + 0.1 is a hair above 0.3 in binary
}

TEST_CASE("mapping clock: disabled means idle at every frame, as a plain sequential run") {
  MappingClockOptions o;
  o.enabled = false;
  MappingClock clock(o);
  clock.Charge(0.0, WithObservations(1000000));
  CHECK(clock.LoadAt(0.001).idle);
  CHECK(clock.LoadAt(0.001).queued == 0);
}

TEST_CASE("mapping clock: bad options are named") {
  MappingClockOptions o;
  o.ms_per_ba_observation = -1;
  CHECK_THROWS_AS(MappingClock(o), dynref::InputError);
  o = {};
  o.max_queue = 0;
  CHECK_THROWS_AS(MappingClock(o), dynref::InputError);
}
