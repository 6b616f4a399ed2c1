// dynref diff: identical, perturbed, missing/extra, reordered, truncated, other schema version.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>

#include "test_support.h"
#include "core/format.h"
#include "trace/trace_diff.h"
#include "trace/trace_reader.h"
#include "trace_sample.h"

using namespace dynref::trace;
using dynref::test::RunDynref;
using dynref::test::SampleTweak;
using dynref::test::WriteSampleTrace;

namespace {
std::string Sample(const std::string& dir, const std::string& name, const SampleTweak& t = {}) {
  const std::string p = dir + "/" + name;
  WriteSampleTrace(p, t);
  return p;
}
}  // namespace

TEST_CASE("diff of identical traces exits 0", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_identical");
  const std::string a = Sample(dir, "a.dtr"), b = Sample(dir, "b.dtr");
  CHECK(DiffTraces(a, b, {}).ExitCode() == 0);
  const auto r = RunDynref("diff '" + a + "' '" + b + "'");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("MATCH") != std::string::npos);
}

TEST_CASE("a float perturbed beyond tolerance is the first divergence, within tolerance passes", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_perturbed");
  SampleTweak t;
  t.after_delta = 1e-6;
  const std::string a = Sample(dir, "a.dtr"), b = Sample(dir, "b.dtr", t);
  const DiffResult d = DiffTraces(a, b, {});
  CHECK(d.ExitCode() == 1);
  REQUIRE(d.divergences.size() == 1);
  const Divergence& first = d.divergences.front();
  CHECK(first.frame == 1);
  CHECK(first.stage == "mgd.temporal");
  CHECK(first.entity == "mp7");
  CHECK(first.field == "after");
  CHECK(first.expected == "0.27666666666666667");
  CHECK(d.stages.at("mgd.temporal").differ == 1);
  CHECK(d.field_errors.at("after").max_abs == Approx(1e-6));
  DiffOptions loose;
  loose.abs_tol = 1e-5;
  CHECK(DiffTraces(a, b, loose).ExitCode() == 0);
  DiffOptions per_field;
  per_field.AddFieldTolerance("after=2e-6");
  CHECK(DiffTraces(a, b, per_field).ExitCode() == 0);
  const auto r = RunDynref("diff '" + a + "' '" + b + "' --rel 1e-9");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("first divergence: frame 1, stage mgd.temporal, prob map_point mp7, field "
                      "after") != std::string::npos);
  CHECK(RunDynref("diff '" + a + "' '" + b + "' --tol after=1e-5").exit_code == 0);
}

TEST_CASE("missing and extra records are reported with per-stage counts") {
  const std::string dir = dynref::test::ScratchDir("diff_missing_extra");
  SampleTweak drop, extra;
  drop.drop_decision = true;
  extra.extra_decision = true;
  const std::string a = Sample(dir, "a.dtr"), b = Sample(dir, "b.dtr", drop),
                    c = Sample(dir, "c.dtr", extra);
  const DiffResult missing = DiffTraces(a, b, {});
  CHECK(missing.ExitCode() == 1);
  REQUIRE(!missing.divergences.empty());
  CHECK(missing.divergences.front().kind == DivergenceKind::kMissing);
  CHECK(missing.divergences.front().entity == "f1.2");
  CHECK(missing.stages.at("sgdo.epipolar").missing == 1);
  const DiffResult added = DiffTraces(a, c, {});
  CHECK(added.ExitCode() == 1);
  REQUIRE(added.divergences.size() == 1);
  CHECK(added.divergences.front().kind == DivergenceKind::kExtra);
  CHECK(added.divergences.front().entity == "f1.9");
  CHECK(added.stages.at("sgdo.epipolar").extra == 1);
}

TEST_CASE("records in another order within a frame still match by key", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_reordered");
  SampleTweak rev;
  rev.reverse_frame1 = true;
  const std::string a = Sample(dir, "a.dtr"), b = Sample(dir, "b.dtr", rev);
  // reverse_frame1 also writes mp7's frame-1 value without the +0.01 offset: one difference.
  const DiffResult d = DiffTraces(a, b, {});
  REQUIRE(d.divergences.size() == 1);
  CHECK(d.divergences.front().entity == "mp7");
  CHECK(d.stages.at("mgd.temporal").missing == 0);
  CHECK(d.stages.at("mgd.temporal").extra == 0);
}

TEST_CASE("truncated trace and other schema version exit 2 naming the problem", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_bad_files");
  const std::string a = Sample(dir, "a.dtr");
  std::string bytes;
  {
    std::ifstream f(a, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  {
    std::ofstream f(dir + "/cut.dtr", std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  std::string next = bytes;
  next[8] = static_cast<char>(kSchemaVersion + 1);  // a schema this build does not know yet
  const std::string next_name = "schema version " + std::to_string(kSchemaVersion + 1);
  {
    std::ofstream f(dir + "/next.dtr", std::ios::binary);
    f.write(next.data(), static_cast<std::streamsize>(next.size()));
  }
  try {
    TraceReader r(dir + "/cut.dtr");
    FAIL("truncated trace accepted");
  } catch (const TraceError& e) {
    CHECK(e.problem() == TraceProblem::kTruncated);
  }
  try {
    TraceReader r(dir + "/next.dtr");
    FAIL(next_name + " accepted");
  } catch (const TraceError& e) {
    CHECK(e.problem() == TraceProblem::kSchemaVersion);
  }
  const auto cut = RunDynref("diff '" + a + "' '" + dir + "/cut.dtr'");
  CHECK(cut.exit_code == 2);
  CHECK(cut.output.find("cut.dtr: truncated") != std::string::npos);
  const auto ver = RunDynref("diff '" + dir + "/next.dtr' '" + a + "'");
  CHECK(ver.exit_code == 2);
  CHECK(ver.output.find(next_name) != std::string::npos);
  CHECK(RunDynref("diff '" + a + "' '" + dir + "/nope.dtr'").exit_code == 2);
  CHECK(RunDynref("trace dump '" + dir + "/cut.dtr'").exit_code == 2);
}

TEST_CASE("a corrupt record inside the body exits 2 naming the problem", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_corrupt");
  const std::string a = Sample(dir, "a.dtr");
  uint64_t offset = 0;
  {
    TraceReader r(a);
    offset = r.groups().at(1).offset;  // the FRAME record of frame 1
  }
  std::string bytes;
  {
    std::ifstream f(a, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  bytes[offset] = 0x55;  // unknown record tag
  {
    std::ofstream f(dir + "/bad.dtr", std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  TraceReader r(dir + "/bad.dtr");  // header and footer are intact
  CHECK_NOTHROW(r.ReadGroup(0));
  try {
    r.ReadGroup(1);
    FAIL("corrupt group accepted");
  } catch (const TraceError& e) {
    CHECK(e.problem() == TraceProblem::kCorrupt);
  }
  const auto d = RunDynref("diff '" + a + "' '" + dir + "/bad.dtr'");
  CHECK(d.exit_code == 2);
  // Schema 2: the block checksum catches it before the decoder sees the bad tag.
  CHECK(d.output.find("corrupt at frame 1: block checksum mismatch") != std::string::npos);
}

TEST_CASE("a canonical JSONL trace (another implementation's text output) diffs against a binary one", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_jsonl");
  const std::string a = Sample(dir, "a.dtr");
  REQUIRE(RunDynref("trace dump '" + a + "' --format jsonl > '" + dir + "/same.jsonl'").exit_code == 0);
  const DiffResult same = DiffTraces(a, dir + "/same.jsonl", {});
  CHECK(same.ExitCode() == 0);
  // Reverse the records of each frame except the FRAME record, and perturb one value.
  std::ifstream in(dir + "/same.jsonl");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::reverse(lines.begin(), lines.end());
  std::string text;
  for (std::string l : lines) {
    const std::string from = "\"entity\":\"mp9\",\"occurrence\":0,\"fields\":{\"in.d_px\":0.69999999999999996";
    if (l.find(from) != std::string::npos) l.replace(l.find(from), from.size(), from.substr(0, from.size() - 19) + "0.70000000000000007");
    text += l + "\n";
  }
  std::ofstream(dir + "/changed.jsonl") << text;
  const DiffResult d = DiffTraces(a, dir + "/changed.jsonl", {});
  REQUIRE(d.divergences.size() == 1);
  CHECK(d.divergences[0].frame == 0);
  CHECK(d.divergences[0].entity == "mp9");
  CHECK(d.divergences[0].field == "in.d_px");
  std::ofstream(dir + "/broken.jsonl") << "{\"frame\":0,\"type\":\"prob\"\n";
  CHECK(RunDynref("diff '" + a + "' '" + dir + "/broken.jsonl'").exit_code == 2);
}

TEST_CASE("diff --summary: final pose deviation and probability differences over the records both runs share", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_summary");
  // Two frames; the candidate's second pose is 3 mm off and turned 2 deg about z, its second
  // probability update differs by 0.4, and it has an extra update the golden run lacks.
  const auto pose = [](int frame, double ty, double deg) {
    const double c = std::cos(deg * M_PI / 180), s = std::sin(deg * M_PI / 180);
    const double t[12] = {c, -s, 0, 0.1, s, c, 0, ty, 0, 0, 1, 0};
    std::string f = "{\"frame\":" + std::to_string(frame) + ",\"type\":\"pose\",\"stage\":\"final\",\"kind\":\"frame\",\"entity\":\"\",\"occurrence\":0,\"fields\":{";
    for (int i = 0; i < 12; ++i) f += (i ? "," : "") + std::string("\"T_wc[") + std::to_string(i) + "]\":" + dynref::FormatDouble17(t[i]);
    return f + "}}\n";
  };
  const auto prob = [](int frame, const std::string& entity, double after) {
    return "{\"frame\":" + std::to_string(frame) + ",\"type\":\"prob\",\"stage\":\"s\",\"kind\":\"feature\",\"entity\":\"" + entity +
           "\",\"occurrence\":0,\"fields\":{\"before\":0.5,\"after\":" + dynref::FormatDouble17(after) + "}}\n";
  };
  std::ofstream(dir + "/g.jsonl") << pose(0, 0, 0) << prob(0, "f0.1", 0.2) << pose(1, 0, 0) << prob(1, "f1.1", 0.5);
  std::ofstream(dir + "/c.jsonl") << pose(0, 0, 0) << prob(0, "f0.1", 0.2) << pose(1, 0.003, 2) << prob(1, "f1.1", 0.9)
                                  << prob(1, "f1.2", 0.7);
  DiffOptions o;
  o.summary = true;
  const DiffResult d = DiffTraces(dir + "/g.jsonl", dir + "/c.jsonl", o);
  REQUIRE(d.pose_frames == std::vector<int64_t>{0, 1});
  CHECK(d.pose_trans_m[0] == 0.0);
  CHECK(d.pose_trans_m[1] == Approx(0.003).margin(1e-12));
  CHECK(d.pose_rot_deg[1] == Approx(2.0).margin(1e-6));
  REQUIRE(d.prob_after_diff.at("s").size() == 2);  // the extra update is not a shared one
  CHECK(d.prob_after_diff.at("s")[1] == Approx(0.4));
  const std::string report = d.Report("g", "c", o);
  CHECK(report.find("summary: final pose deviation over 2 frames") != std::string::npos);
  CHECK(report.find("first frame straying more than 1 mm: 1") != std::string::npos);
  CHECK(report.find("  s,2,") != std::string::npos);
  const auto cli = RunDynref("diff '" + dir + "/g.jsonl' '" + dir + "/c.jsonl' --summary");
  CHECK(cli.exit_code == 1);
  CHECK(cli.output.find("translation_mm,2,") != std::string::npos);
}

TEST_CASE("diff: an empty JSONL trace exits 2 like an empty binary one and --tol of an unknown field is refused (issue 37)", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("diff_cli_issue37");
  const std::string a = Sample(dir, "a.dtr");
  REQUIRE(RunDynref("trace dump '" + a + "' --format jsonl > '" + dir + "/a.jsonl'").exit_code == 0);
  std::ofstream(dir + "/empty.jsonl").flush();
  const auto empty = RunDynref("diff '" + dir + "/a.jsonl' '" + dir + "/empty.jsonl'");
  CHECK(empty.exit_code == 2);
  CHECK(empty.output.find("empty.jsonl: empty JSONL trace (no records)") != std::string::npos);
  const auto bogus = RunDynref("diff '" + a + "' '" + a + "' --tol bogus_field=1");
  CHECK(bogus.exit_code == 2);
  CHECK(bogus.output.find("--tol: no float field 'bogus_field' in the compared records") != std::string::npos);
  // A field the records have (or its base name) is accepted.
  const DiffResult r = DiffTraces(a, a, {});
  REQUIRE_FALSE(r.field_errors.empty());
  const std::string field = r.field_errors.begin()->first;
  CHECK(RunDynref("diff '" + a + "' '" + a + "' --tol '" + field.substr(0, field.find('[')) + "=1'").exit_code == 0);
}
