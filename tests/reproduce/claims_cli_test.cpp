// `dynref reproduce claims`: writes the ledger, names a missing row by file and line (exit 2), and
// the committed reports/CLAIMS.md is the one the committed reports give.
#include <catch2/catch.hpp>
#include <filesystem>
#include <regex>
#include <set>

#include "test_support.h"

using namespace dynref;

namespace {

// The reports' Markdown and paper tables copied to a scratch folder (the ledger written beside them).
std::string CopyReportsForCli(const std::string& name) {
  namespace fs = std::filesystem;
  const std::string dir = test::ScratchDir(name);
  fs::create_directories(dir + "/paper-tables");
  for (const auto& e : fs::directory_iterator(test::SourcePath("reports")))
    if (e.path().extension() == ".md" && e.path().filename() != "CLAIMS.md")
      fs::copy_file(e.path(), dir + "/" + e.path().filename().string());
  for (const auto& e : fs::directory_iterator(test::SourcePath("reports/paper-tables")))
    fs::copy_file(e.path(), dir + "/paper-tables/" + e.path().filename().string());
  return dir;
}

// The ledger without its "Written by" line (which names the build's commit).
std::string WithoutProvenance(const std::string& md) {
  return std::regex_replace(md, std::regex("Written by `dynref reproduce claims` \\(dynref [^)]*\\)"), "");
}

}  // namespace

TEST_CASE("reproduce claims writes the ledger, and the committed CLAIMS.md matches the committed reports", "[cli]") {
  const std::string dir = CopyReportsForCli("claims_cli");
  const test::CommandResult r =
      test::RunDynref("reproduce claims --reports " + test::Quote(dir) + " --out " + test::Quote(dir + "/CLAIMS.md"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string md = test::ReadFileBytes(dir + "/CLAIMS.md");
  const std::regex row("\\n\\| (00[0-4])-C[0-9]+ \\| ");
  int rows = 0;
  std::set<std::string> papers;
  for (auto it = std::sregex_iterator(md.begin(), md.end(), row); it != std::sregex_iterator(); ++it, ++rows)
    papers.insert((*it)[1].str());
  CHECK(rows >= 40);
  CHECK(papers.size() == 5);
  const std::string committed = test::ReadFileBytes(test::SourcePath("reports/CLAIMS.md"));
  REQUIRE(!committed.empty());
  CHECK(WithoutProvenance(committed) == WithoutProvenance(md));  // regenerate: dynref reproduce claims
}

TEST_CASE("reproduce claims: a report without a row the ledger reads is bad input naming file and line", "[cli]") {
  const std::string dir = CopyReportsForCli("claims_cli_missing");
  const std::string path = dir + "/blur-table3.md";
  const std::string text = test::ReadFileBytes(path);
  test::WritePatched(text, "| walking_rpy (fr3/w/rpy) |", "| walking_rpy (renamed) |", path);
  test::ExpectBadInput("reproduce claims --reports " + test::Quote(dir) + " --out " + test::Quote(dir + "/C.md"),
                       "blur-table3.md:18: no row 'walking_rpy (fr3/w/rpy)'");
  CHECK_FALSE(test::FileExists(dir + "/C.md"));
}
