// `dynref reproduce --list` names every table, each name is a working subcommand, and
// `dynref run --set` changes exactly the named stage parameter.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "reproduce/paper_table.h"
#include "reproduce/table_list.h"
#include "test_support.h"

using namespace dynref;

TEST_CASE("reproduce --list names every table, and each is a subcommand with help", "[cli]") {
  const test::CommandResult r = test::RunDynref("reproduce --list");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(!reproduce::ReproducibleTables().empty());
  for (const auto& t : reproduce::ReproducibleTables()) {
    CHECK(r.output.find(t.name + "\t" + t.paper + "\treports/" + t.name + ".md") != std::string::npos);
    const test::CommandResult h = test::RunDynref("reproduce " + t.name + " --help");
    INFO(t.name);
    CHECK(h.exit_code == 0);
    CHECK(h.output.find("--out") != std::string::npos);
  }
  const test::CommandResult none = test::RunDynref("reproduce");
  CHECK(none.exit_code == 2);
  CHECK(none.output.find("--list") != std::string::npos);
}

TEST_CASE("run --set changes one stage parameter and records it, a malformed --set is bad input", "[cli]") {
  const std::string dir = test::ScratchDir("run_set");
  REQUIRE(test::RunDynref("synth --preset walking_xyz --frames 30 --seed 1 --detections yolo-like --out " + dir + "/seq")
              .exit_code == 0);
  const std::string base = "run --sequence " + dir + "/seq --detections " + dir + "/seq/detections/yolo-like --no-progress " +
                           "--config " + test::SourcePath("configs/sgdo_nodense.yaml");
  const test::CommandResult r = test::RunDynref(base + " --out " + dir + "/run --set sgdo.depth.eta=0.05");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::ifstream in(dir + "/run/run.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  bool found = false;
  for (const auto& st : j["config"]["stages"])
    if (st["name"] == "sgdo.depth") {
      CHECK(st["params"]["eta"]["value"] == "0.05");
      CHECK(st["params"]["eta"]["source"] == "dynref run --set");
      CHECK(st["params"]["lambda"]["source"] != "dynref run --set");
      found = true;
    }
  CHECK(found);
  test::ExpectBadInput(base + " --out " + dir + "/bad1 --set sgdo.depth.eta", "--set");
  test::ExpectBadInput(base + " --out " + dir + "/bad2 --set eta=1", "--set");
  test::ExpectBadInput(base + " --out " + dir + "/bad3 --set sgdo.depth.nope=1", "no parameter nope");
  test::ExpectBadInput(base + " --out " + dir + "/bad4 --set sgdo.nostage.eta=1", "no stage sgdo.nostage");
}

TEST_CASE("paper tables: quoted cells keep their commas, empty cells are NaN, notes are kept") {
  const std::string dir = test::ScratchDir("paper_table");
  const std::string path = test::WriteText(dir + "/t.csv",
                                           "# Source: copied from somewhere\n"
                                           "# Table 9. Caption (ms)\n"
                                           "Systems,Time,Hardware\n"
                                           "A,31.21,\"CPU, GPU\"\n"
                                           "B,,\"say \"\"x\"\"\"\n"
                                           "# B's time was printed as '-'\n");
  const reproduce::PaperTable t = reproduce::ReadPaperTable(path);
  CHECK(t.caption == "Table 9. Caption (ms)");
  REQUIRE(t.notes.size() == 1);
  CHECK(t.notes[0] == "B's time was printed as '-'");
  REQUIRE(t.ordered.size() == 2);
  CHECK(t.ordered[0][2] == "CPU, GPU");
  CHECK(t.ordered[1][2] == "say \"x\"");
  CHECK(t.Cell("A", "Time") == Approx(31.21));
  CHECK(std::isnan(t.Cell("B", "Time")));
  CHECK(std::isnan(t.Cell("C", "Time")));
  CHECK(std::isnan(t.Cell("A", "Nope")));
}
