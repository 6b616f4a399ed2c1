// The schema README is enough to write a trace: ref/trace/dtr_from_jsonl.py (an independent
// Python writer) re-encodes a JSONL dump byte-identically, and in another record order within
// each frame the diff still matches by key.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>

#include "test_support.h"
#include "trace_sample.h"

using dynref::test::RunDynref;

namespace {
}  // namespace

TEST_CASE("an independent Python writer following the README produces traces dynref diffs", "[cli]") {
  // python3 is a test dependency (scripts/install-deps.sh): missing it is a failure, not a skip.
  if (std::system("python3 --version > /dev/null 2>&1") != 0)
    FAIL("python3 not found: install it (scripts/install-deps.sh) to run this test");
  const std::string dir = dynref::test::ScratchDir("trace_python_writer");
  dynref::test::WriteSampleTrace(dir + "/a.dtr");
  REQUIRE(RunDynref("trace dump '" + dir + "/a.dtr' --format jsonl > '" + dir + "/r.jsonl'").exit_code == 0);
  REQUIRE(RunDynref("trace dump '" + dir + "/a.dtr' --format jsonl --header > '" + dir + "/h.jsonl'").exit_code == 0);
  const std::string py = "python3 '" + dynref::test::SourcePath("ref/trace/dtr_from_jsonl.py") +
                         "' '" + dir + "/r.jsonl' ";
  REQUIRE(std::system((py + "'" + dir + "/same.dtr' --header '" + dir + "/h.jsonl'").c_str()) == 0);
  CHECK(dynref::test::ReadFileBytes(dir + "/same.dtr") == dynref::test::ReadFileBytes(dir + "/a.dtr"));
  REQUIRE(std::system((py + "'" + dir + "/rev.dtr' --reverse-within-frame").c_str()) == 0);
  const auto r = RunDynref("diff '" + dir + "/a.dtr' '" + dir + "/rev.dtr'");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("MATCH") != std::string::npos);
}

TEST_CASE("the Python writer writes schema 3 from a schema 2 dump (associated = map_point_id)", "[cli]") {
  if (std::system("python3 --version > /dev/null 2>&1") != 0)
    FAIL("python3 not found: install it (scripts/install-deps.sh) to run this test");
  const std::string dir = dynref::test::ScratchDir("trace_python_writer_v2");
  const std::string v2 = dynref::test::SourcePath("tests/data/trace_v2/bench_schema2.dtr");
  REQUIRE(RunDynref("trace dump '" + v2 + "' --format jsonl > '" + dir + "/r.jsonl'").exit_code == 0);
  // A schema 2 era JSONL has no associated_map_point_id: strip it as such a dump would be.
  REQUIRE(std::system(("sed -i 's/,\"associated_map_point_id\":\"[-0-9]*\"//' '" + dir + "/r.jsonl'").c_str()) == 0);
  REQUIRE(dynref::test::ReadFileBytes(dir + "/r.jsonl").find("associated") == std::string::npos);
  const std::string py = "python3 '" + dynref::test::SourcePath("ref/trace/dtr_from_jsonl.py") + "' ";
  REQUIRE(std::system((py + "'" + dir + "/r.jsonl' '" + dir + "/v3.dtr'").c_str()) == 0);
  const auto head = RunDynref("trace dump '" + dir + "/v3.dtr' --header");
  CHECK(head.output.find("schema_version,3") != std::string::npos);
  const auto d = RunDynref("diff '" + v2 + "' '" + dir + "/v3.dtr'");
  INFO(d.output);
  CHECK(d.exit_code == 0);
  // and the JSONL without the field diffs identical to the schema 2 trace as well
  CHECK(RunDynref("diff '" + v2 + "' '" + dir + "/r.jsonl'").exit_code == 0);
}
