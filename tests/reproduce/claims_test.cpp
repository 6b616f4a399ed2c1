// The claims ledger: verdicts on hand-made numbers, and the registry against the committed reports.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include "core/error.h"
#include "reproduce/claims.h"
#include "reproduce/claims_ledger.h"
#include "test_support.h"

using namespace dynref;
using namespace dynref::reproduce;

namespace {

Measured M(double mean, double sd) { return {mean, sd, sd > 0}; }

// The committed reports' Markdown and the paper tables, copied to a scratch folder.
std::string CopyReports(const std::string& name) {
  namespace fs = std::filesystem;
  const std::string dir = test::ScratchDir(name);
  fs::create_directories(dir + "/paper-tables");
  for (const auto& e : fs::directory_iterator(test::SourcePath("reports")))
    if (e.path().extension() == ".md") fs::copy_file(e.path(), dir + "/" + e.path().filename().string());
  for (const auto& e : fs::directory_iterator(test::SourcePath("reports/paper-tables")))
    fs::copy_file(e.path(), dir + "/paper-tables/" + e.path().filename().string());
  return dir;
}

}  // namespace

TEST_CASE("claims verdict: an ordering, with and without overlapping S.D. intervals") {
  CHECK(CompareLower(M(1.0, 0.1), M(2.0, 0.1), true) == Verdict::kReproduced);
  CHECK(CompareLower(M(1.0, 0.6), M(2.0, 0.6), true) == Verdict::kReproducedWithinSd);
  CHECK(CompareLower(M(1.0, 0.4), M(2.0, 0.4), true) == Verdict::kReproduced);  // 0.8 < 1.0: no overlap
  CHECK(CompareLower(M(2.0, 0.6), M(1.0, 0.6), true) == Verdict::kNotReproducedWithinSd);
  CHECK(CompareLower(M(2.0, 0.1), M(1.0, 0.1), true) == Verdict::kNotReproduced);
  CHECK(CompareLower(M(2.0, 0.0), M(1.0, 0.0), true) == Verdict::kNotReproduced);
  CHECK(CompareLower(M(1.0, 0.0), M(1.0, 0.0), true) == Verdict::kNotReproduced);  // strict: a tie fails
  CHECK(CompareLower(M(1.0, 0.0), M(1.0, 0.0), false) == Verdict::kReproduced);    // no worse: a tie holds
}

TEST_CASE("claims verdict: lowest of several is the worst pairwise verdict") {
  CHECK(LowestOf(M(1.0, 0.1), {M(2.0, 0.1), M(3.0, 0.1)}) == Verdict::kReproduced);
  CHECK(LowestOf(M(1.0, 0.1), {M(3.0, 0.1), M(1.1, 0.1)}) == Verdict::kReproducedWithinSd);
  CHECK(LowestOf(M(1.0, 0.1), {M(0.95, 0.1), M(3.0, 0.1)}) == Verdict::kNotReproducedWithinSd);
  CHECK(LowestOf(M(1.0, 0.1), {M(1.1, 0.1), M(0.5, 0.1)}) == Verdict::kNotReproduced);
  CHECK(Worse(Verdict::kReproduced, Verdict::kNotMeasured) == Verdict::kNotMeasured);
  CHECK(Worse(Verdict::kNotReproduced, Verdict::kReproducedWithinSd) == Verdict::kNotReproduced);
}

TEST_CASE("claims verdict: thresholds and ranges against mean ± S.D.") {
  CHECK(CompareThreshold(M(97.3, 1.1), 95.0, true) == Verdict::kReproduced);
  CHECK(CompareThreshold(M(95.9, 1.5), 95.0, true) == Verdict::kReproducedWithinSd);
  CHECK(CompareThreshold(M(94.6, 1.0), 95.0, true) == Verdict::kNotReproducedWithinSd);
  CHECK(CompareThreshold(M(3.6, 7.9), 44.34, true) == Verdict::kNotReproduced);
  CHECK(CompareThreshold(M(30.6, 0.0), 46.0, false) == Verdict::kReproduced);
  CHECK(CompareThreshold(M(63.2, 0.0), 58.4, false) == Verdict::kNotReproduced);
  CHECK(CompareThreshold(M(57.0, 2.0), 58.4, false) == Verdict::kReproducedWithinSd);
  CHECK(InRange(M(47.9, 0.2), 20.0, 50.0) == Verdict::kReproduced);
  CHECK(InRange(M(49.5, 1.0), 20.0, 50.0) == Verdict::kReproducedWithinSd);
  CHECK(InRange(M(50.5, 1.0), 20.0, 50.0) == Verdict::kNotReproducedWithinSd);
  CHECK(InRange(M(53.0, 4.6), 20.0, 50.0) == Verdict::kNotReproducedWithinSd);
  CHECK(InRange(M(54.7, 4.6), 20.0, 50.0) == Verdict::kNotReproduced);
  CHECK(InRange(M(67.5, 1.4), 20.0, 50.0) == Verdict::kNotReproduced);
  CHECK(InRange(M(0.8, 0.0), 16.5, 35.0) == Verdict::kNotReproduced);
}

TEST_CASE("claims verdict: per-seed improvement is the mean and population S.D. of the per-seed cuts") {
  const Measured m = PerSeedImprovement({1.0, 2.0}, {10.0, 10.0});  // cuts 90 and 80 %
  CHECK(m.mean == Approx(85.0));
  CHECK(m.sd == Approx(5.0));
  CHECK(m.has_sd);
  CHECK_THROWS(PerSeedImprovement({1.0}, {1.0, 2.0}));
  CHECK_THROWS(PerSeedImprovement({1.0}, {0.0}));
}

TEST_CASE("claims registry: at least 40 claims, all five papers, unique ids, every claim cites its source") {
  const std::vector<Claim> claims = AllClaims();
  CHECK(claims.size() >= 40);
  std::map<std::string, int> per_paper;
  std::set<std::string> ids;
  for (const Claim& c : claims) {
    INFO(c.id);
    ++per_paper[c.paper];
    CHECK(ids.insert(c.id).second);
    CHECK(c.id.rfind(c.paper + "-C", 0) == 0);
    CHECK(std::regex_search(c.source, std::regex("^(Sec\\. [0-9.]+|Abstract)")));
    CHECK(!c.statement.empty());
  }
  CHECK(per_paper.size() == 5);
  for (const char* p : {"000", "001", "002", "003", "004"}) CHECK(per_paper[p] >= 5);
}

TEST_CASE("claims registry: every claim resolves against the committed reports, explanations cite existing files") {
  const std::vector<ClaimResult> results = ResolveClaims(AllClaims(), test::SourcePath("reports"));
  REQUIRE(results.size() == AllClaims().size());
  const std::regex cited("((ref|reports)/[A-Za-z0-9_./-]+\\.(md|h|cpp))");
  int not_reproduced = 0, explained = 0;
  for (const ClaimResult& r : results) {
    INFO(r.claim.id);
    if (r.claim.kind != ClaimKind::kNotMeasured) CHECK(r.verdict != Verdict::kNotMeasured);
    const bool failed = r.verdict == Verdict::kNotReproduced || r.verdict == Verdict::kNotReproducedWithinSd;
    not_reproduced += failed;
    if (!failed || r.claim.explanation.empty()) continue;
    ++explained;
    std::smatch m;
    REQUIRE(std::regex_search(r.claim.explanation, m, cited));  // an explanation says where it was measured
    for (auto it = std::sregex_iterator(r.claim.explanation.begin(), r.claim.explanation.end(), cited);
         it != std::sregex_iterator(); ++it)
      CHECK(test::FileExists(test::SourcePath((*it)[1].str())));
  }
  CHECK(not_reproduced > 0);
  CHECK(explained > 0);
}

TEST_CASE("claims registry: a report regenerated without a row the ledger reads fails with its file and line") {
  const std::string dir = CopyReports("claims_dropped_row");
  const std::string path = dir + "/sgdo-table6.md";
  const std::string text = test::ReadFileBytes(path);
  const std::string row = "| walking_rpy (dynref) |";
  const size_t at = text.find(row);
  REQUIRE(at != std::string::npos);
  const size_t end = text.find('\n', at);
  test::WriteText(path, text.substr(0, at) + text.substr(end + 1));
  try {
    ResolveClaims(AllClaims(), dir);
    FAIL("no error for the dropped row");
  } catch (const InputError& e) {
    CHECK(e.file() == path);
    CHECK(e.line() > 0);
    CHECK(std::string(e.what()).find("walking_rpy (dynref)") != std::string::npos);
  }
}

TEST_CASE("claims ledger: every claim is a row, the counts add up, and the text is deterministic") {
  const std::vector<ClaimResult> results = ResolveClaims(AllClaims(), test::SourcePath("reports"));
  const std::string md = ClaimsLedgerMarkdown(results, "");
  CHECK(md == ClaimsLedgerMarkdown(ResolveClaims(AllClaims(), test::SourcePath("reports")), ""));
  for (const ClaimResult& r : results) CHECK(md.find("| " + r.claim.id + " | ") != std::string::npos);
  CHECK(md.find("| all | " + std::to_string(results.size()) + " |") != std::string::npos);
  CHECK(md.find("](sgdo-table6.md?plain=1#L") != std::string::npos);
}
