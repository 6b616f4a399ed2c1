// The strict reader of the reports' Markdown tables (reproduce/report_reader.h) on a small fixture.
#include <catch2/catch.hpp>

#include "core/error.h"
#include "reproduce/report_reader.h"
#include "test_support.h"

using namespace dynref;
using namespace dynref::reproduce;

namespace {

// Line numbers matter: the fixture's line N is the N-th line below.
const char* kFixtureReport =
    "# A table (seed 001) on synthetic sequences\n"                                                   // 1
    "\n"                                                                                               // 2
    "Written by `dynref reproduce toy-table --frames 120 --seeds 1,2,3 --detections yolo-like` "
    "(dynref 0.1.0, commit abc123def456). Do not edit by hand.\n"                                      // 3
    "\n"                                                                                               // 4
    "## ATE RMSE (m): dynref on synthetic data\n"                                                     // 5
    "\n"                                                                                               // 6
    "| Sequence | orb | sgdo | ratio | tracked |\n"                                                    // 7
    "|---|---|---|---|---|\n"                                                                          // 8
    "| walking_xyz (dynref) | 0.5360 ± 0.0911 | 0.0135 | 1.6x | 0.2896 (900/900) |\n"                 // 9
    "| sitting_static (dynref) | 97.3 ± 1.1 % | - | never initialised | abc |\n"                      // 10
    "\n"                                                                                               // 11
    "## Rejected features\n"                                                                           // 12
    "\n"                                                                                               // 13
    "| Sequence | Variant | precision | recall | F1 | moving: precision | recall |\n"                  // 14
    "|---|---|---|---|---|---|---|\n"                                                                  // 15
    "| walking_xyz | (G) | 56.9 | 32.8 | 41.6 | 56.0 | 35.0 |\n"                                        // 16
    "| walking_xyz | (S) | 64.9 | 86.2 | 74.1 | 59.5 | 85.9 |\n"                                        // 17
    "\n"                                                                                               // 18
    "## Per seed: ATE RMSE (m)\n"                                                                      // 19
    "\n"                                                                                               // 20
    "| Sequence | Variant | seeds 1,2,3 |\n"                                                           // 21
    "|---|---|---|\n"                                                                                  // 22
    "| walking_xyz | orb | 0.6615 (300) 0.4986 (300) 0.4479 (298) |\n"                                // 23
    "| walking_xyz | mgd | 0.0074 0.0091 0.0075 |\n"                                                  // 24
    "\n"                                                                                               // 25
    "## ATE RMSE (m): again\n";                                                                        // 26

std::string FixturePath() {
  return test::WriteText(test::ScratchDir("report_reader") + "/toy-table.md", kFixtureReport);
}

// The InputError's file and line when `f` throws one; line -1 when it does not throw.
template <typename F>
std::pair<std::string, int> ErrorAt(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return {e.file(), e.line()};
  }
  return {"", -1};
}

}  // namespace

TEST_CASE("report reader: mean ± S.D., plain numbers, suffixes and the row's line") {
  const std::string path = FixturePath();
  const ReportTable t = ReadReportTable(path, "ATE RMSE (m): dynref");
  CHECK(t.heading_line == 5);
  const ReportValue orb = ReadReportValue(t, "walking_xyz (dynref)", "orb");
  CHECK(orb.mean == Approx(0.5360));
  CHECK(orb.sd == Approx(0.0911));
  CHECK(orb.has_sd);
  CHECK(orb.line == 9);
  CHECK(orb.file == path);
  const ReportValue sgdo = ReadReportValue(t, "walking_xyz (dynref)", "sgdo");
  CHECK(sgdo.mean == Approx(0.0135));
  CHECK_FALSE(sgdo.has_sd);
  CHECK(ReadReportValue(t, "walking_xyz (dynref)", "ratio").mean == Approx(1.6));
  CHECK(ReadReportValue(t, "walking_xyz (dynref)", "tracked").mean == Approx(0.2896));
  const ReportValue pct = ReadReportValue(t, "sitting_static (dynref)", "orb");
  CHECK(pct.mean == Approx(97.3));
  CHECK(pct.sd == Approx(1.1));
  CHECK_FALSE(ReadReportValue(t, "sitting_static (dynref)", "sgdo").numeric);
  CHECK_FALSE(ReadReportValue(t, "sitting_static (dynref)", "ratio").numeric);
}

TEST_CASE("report reader: rows by their leading cells, repeated columns by occurrence, per-seed lists") {
  const std::string path = FixturePath();
  const ReportTable pr = ReadReportTable(path, "Rejected features");
  CHECK(ReadReportValue(pr, "walking_xyz | (S)", "recall#1").mean == Approx(86.2));
  CHECK(ReadReportValue(pr, "walking_xyz | (S)", "recall#2").mean == Approx(85.9));
  CHECK(ReadReportValue(pr, "walking_xyz | (G)", "F1").line == 16);
  const ReportTable seeds = ReadReportTable(path, "Per seed");
  const ReportValue orb = ReadReportValue(seeds, "walking_xyz | orb", "seeds 1,2,3");
  REQUIRE(orb.seeds.size() == 3);
  CHECK(orb.seeds[2] == Approx(0.4479));
  CHECK(orb.mean == Approx((0.6615 + 0.4986 + 0.4479) / 3));
  const ReportValue mgd = ReadReportValue(seeds, "walking_xyz | mgd", "seeds 1,2,3");
  REQUIRE(mgd.seeds.size() == 3);
  // population S.D. of 0.0074, 0.0091, 0.0075
  CHECK(mgd.sd == Approx(0.000778).epsilon(0.01));
  const ReportProvenance p = ReadReportProvenance(path, ReadReportLines(path));
  CHECK(p.seeds == "1,2,3");
  CHECK(p.frames == "120");
  CHECK(p.commit == "abc123def456");
}

TEST_CASE("report reader: a missing or ambiguous heading, row or column and a bad cell name file and line") {
  const std::string path = FixturePath();
  CHECK(ErrorAt([&] { ReadReportTable(path, "No such heading"); }) == std::make_pair(path, 0));
  CHECK(ErrorAt([&] { ReadReportTable(path, "ATE RMSE (m)"); }).second == 26);  // two headings match
  CHECK(ErrorAt([&] { ReadReportTable(path, "ATE RMSE (m): again"); }).second == 26);  // no table below
  const ReportTable t = ReadReportTable(path, "ATE RMSE (m): dynref");
  CHECK(ErrorAt([&] { ReadReportValue(t, "walking_rpy (dynref)", "orb"); }).second == 5);
  CHECK(ErrorAt([&] { ReadReportValue(t, "walking_xyz (dynref)", "mgd"); }).second == 5);
  CHECK(ErrorAt([&] { ReadReportValue(t, "sitting_static (dynref)", "tracked"); }).second == 10);
  CHECK(ErrorAt([&] { ReadReportValue(t, "walking_xyz (dynref)", "orb"); }).second == -1);
  const ReportTable pr = ReadReportTable(path, "Rejected features");
  CHECK(ErrorAt([&] { ReadReportValue(pr, "walking_xyz | (S)", "recall"); }).second == 12);  // two "recall"
  CHECK(ErrorAt([&] { ReadReportValue(pr, "walking_xyz", "F1"); }).second == 17);           // two rows
  CHECK(ErrorAt([&] { ReadReportLines(path + ".missing"); }).first == path + ".missing");
  CHECK(ErrorAt([] { ParseReportCell("0.12 ± x", "f.md", 3); }) == std::make_pair(std::string("f.md"), 3));
  CHECK(ErrorAt([] { ParseReportCell("0.12 m", "f.md", 4); }).second == 4);
  CHECK(ErrorAt([] { ParseReportCell("0.12", "f.md", 4); }).second == -1);
}
