// The table seam of `dynref reproduce`: a table registered here, in the test, runs through the same
// generic loop as the built-in tables (reproduce::AddTableSubcommands, which cli/cmd_reproduce.cpp
// calls) without a line in any other file.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <catch2/catch.hpp>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "reproduce/table_registry.h"
#include "reproduce/table_list.h"

using namespace dynref;

namespace {

// Plain seed parsers standing in for cli::ParseSeed / ParseSeedList (no ranges needed here).
reproduce::SeedParsers TestSeedParsers() {
  return {[](const std::string& text, const std::string&) { return static_cast<uint64_t>(std::stoull(text)); },
          [](const std::vector<std::string>& items, const std::string&) {
            std::vector<uint64_t> out;
            for (const std::string& s : items) out.push_back(std::stoull(s));
            return out;
          }};
}

struct ToyArgs : reproduce::MatrixArgs {
  ToyArgs() {
    out = "reports/toy-table.md";
    work = "dynref-work/toy";
    frames = 40;
  }
  int knob = 1;  // a table's own option
};

// The toy table's whole definition: its --list row, its options (the shared block + --knob) and
// its runner, which records what it was given.
reproduce::TableDef ToyTable(std::shared_ptr<ToyArgs>& seen) {
  return {"toy-table", "999 toy paper", "a table that only records its arguments", "Toy table for the seam test",
          [&seen](CLI::App& app) {
            auto a = std::make_shared<ToyArgs>();
            reproduce::MatrixHelp help;
            help.detections = "Synthetic detection mode (default yolo-like)";
            help.sequences = "Presets";
            help.seed = "One seed";
            reproduce::AddMatrixOptions(app, *a, help);
            app.add_option("--knob", a->knob, "The toy's own option");
            reproduce::AddReuseCollect(app, *a, "Reuse", "Only read");
            return reproduce::TableCommand{a, [a, &seen] {
                                             seen = a;
                                             return 7;
                                           }};
          }};
}

// Parses `args` under `reproduce` and runs the selected table (what main does with the commands).
int RunParsed(const reproduce::TableRegistry& tables, std::vector<std::string> args) {
  CLI::App root("test");
  CLI::App* rep = root.add_subcommand("reproduce", "");
  const auto commands = reproduce::AddTableSubcommands(*rep, tables, TestSeedParsers());
  args.insert(args.begin(), "reproduce");
  std::reverse(args.begin(), args.end());  // CLI11's vector form takes the arguments last first
  root.parse(args);
  for (const auto& [app, run] : commands)
    if (app->parsed()) return run();
  return -1;
}

}  // namespace

TEST_CASE("a toy table registered in the test runs through the generic reproduce loop") {
  std::shared_ptr<ToyArgs> seen;
  reproduce::TableRegistry tables;
  tables.Add(ToyTable(seen));
  REQUIRE(tables.Find("toy-table") != nullptr);
  CHECK(tables.Find("toy-table")->Report() == "reports/toy-table.md");

  CHECK(RunParsed(tables, {"toy-table", "--frames", "60", "--seeds", "4,5", "--sequences", "walking_xyz,crowd",
                           "--knob", "3", "--reuse"}) == 7);
  REQUIRE(seen != nullptr);
  CHECK(seen->frames == 60);
  CHECK(seen->seeds == std::vector<uint64_t>{4, 5});
  CHECK(seen->sequences == std::vector<std::string>{"walking_xyz", "crowd"});
  CHECK(seen->knob == 3);
  CHECK(seen->reuse);
  CHECK_FALSE(seen->collect);
  CHECK(seen->out == "reports/toy-table.md");

  seen.reset();
  CHECK(RunParsed(tables, {"toy-table", "--seed", "9", "--collect", "--detections", "ideal"}) == 7);
  REQUIRE(seen != nullptr);
  CHECK(seen->seeds == std::vector<uint64_t>{9});
  CHECK(seen->collect);
  CHECK(seen->detections == "ideal");
  CHECK(seen->frames == 40);  // the toy's own default
}

TEST_CASE("the table registry keeps --list order (paper, then name) and refuses a name twice") {
  std::shared_ptr<ToyArgs> seen;
  reproduce::TableRegistry tables;
  reproduce::TableDef b = ToyTable(seen);
  b.name = "b-table";
  reproduce::TableDef a = ToyTable(seen);
  a.name = "a-table";
  reproduce::TableDef early = ToyTable(seen);
  early.name = "z-table";
  early.paper = "000 first";
  tables.Add(b);
  tables.Add(a);
  tables.Add(early);
  REQUIRE(tables.Tables().size() == 3);
  CHECK(tables.Tables()[0].name == "z-table");
  CHECK(tables.Tables()[1].name == "a-table");
  CHECK(tables.Tables()[2].name == "b-table");
  CHECK_THROWS_AS(tables.Add(a), std::logic_error);
  reproduce::TableDef no_runner{"c-table", "999", "", "", {}};
  CHECK_THROWS_AS(tables.Add(no_runner), std::logic_error);
}

TEST_CASE("every built-in table registers itself once, and --list is the registry") {
  reproduce::TableRegistry tables;
  reproduce::RegisterBuiltinTables(tables);
  const auto& listed = reproduce::ReproducibleTables();
  REQUIRE(tables.Tables().size() == listed.size());
  std::set<std::string> names;
  for (size_t i = 0; i < listed.size(); ++i) {
    CHECK(tables.Tables()[i].name == listed[i].name);
    CHECK(tables.Tables()[i].paper == listed[i].paper);
    CHECK(!tables.Tables()[i].help.empty());
    names.insert(listed[i].name);
  }
  CHECK(names.size() == listed.size());
  // Each table's options include the shared block.
  CLI::App root("test");
  CLI::App* rep = root.add_subcommand("reproduce", "");
  for (const auto& [app, run] : reproduce::AddTableSubcommands(*rep, tables, TestSeedParsers())) {
    INFO(app->get_name());
    CHECK(app->get_option_no_throw("--out") != nullptr);
    CHECK(app->get_option_no_throw("--seeds") != nullptr);
    CHECK(app->get_option_no_throw("--reuse") != nullptr);
  }
}
