#include <catch2/catch.hpp>

#include "test_support.h"

using dynref::test::RunDynref;

TEST_CASE("cli: --help exits 0, unknown flags and commands exit 2", "[cli]") {
  CHECK(RunDynref("--help").exit_code == 0);
  CHECK(RunDynref("version --help").exit_code == 0);
  const auto bad_flag = RunDynref("version --no-such-flag");
  CHECK(bad_flag.exit_code == 2);
  CHECK(RunDynref("no-such-command").exit_code == 2);
  CHECK(RunDynref("").exit_code == 2);
}
