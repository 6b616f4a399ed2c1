// Writer -> reader -> dump round trip, determinism, levels, atomic close.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "test_support.h"
#include "trace/trace_dump.h"
#include "trace/trace_reader.h"
#include "trace/trace_source.h"
#include "trace_sample.h"

using namespace dynref::trace;

namespace {
std::string Dump(const std::string& path, DumpOptions o = {}) {
  TraceReader r(path);
  std::ostringstream s;
  WriteDump(r, o, s);
  return s.str();
}
}  // namespace

TEST_CASE("writer to reader round trip keeps every value bit-exact") {
  const std::string dir = dynref::test::ScratchDir("trace_roundtrip");
  dynref::test::WriteSampleTrace(dir + "/trace.dtr");
  TraceReader r(dir + "/trace.dtr");
  CHECK(r.level() == Level::kFull);
  CHECK(r.end_state() == "complete");
  CHECK(r.HeaderValue("method") == "sample");
  CHECK(r.HeaderValue("input_sha256:rgb.txt") == "abc");
  REQUIRE(r.groups().size() == 3);
  const std::vector<Record> recs = r.ReadGroup(1);
  REQUIRE(recs.size() == 12);  // frame, pose, count, 4 obs, 2 prob, residual, decision, pose
  CHECK(recs[0].type == RecordType::kFrame);
  CHECK(recs[0].timestamp == 1305031102.175304 + 0.033);
  CHECK(recs[1].T_wc[7] == 1.0 / 3.0);
  CHECK(recs[4].v == 200.5 / 3.0 + 1);
  CHECK(recs[4].map_point_id == 8);
  CHECK(recs[4].associated_map_point_id == 8);
  CHECK(recs[5].map_point_id == -1);             // f1.2: suppressed ...
  CHECK(recs[5].associated_map_point_id == 20);  // ... but associated with mp20 (schema 3)
  CHECK(recs[3].associated_map_point_id == -1);  // f1.0: never associated
  CHECK(r.schema_version() == kSchemaVersion);
  CHECK(kSchemaVersion == 3);
  CHECK(recs[4].descriptor_hash == 0x1234567890abcdefULL + 1);
  CHECK(recs[7].stage == "mgd.temporal");
  CHECK(recs[7].after == 0.8 / 3.0 + 0.01);
  CHECK(recs[7].inputs.at(1).name == "n_obs");
  CHECK(recs[9].residual_start.at(2) == 1e-3);
  CHECK(recs[9].inlier);
  CHECK(recs[10].reason == "epipolar distance 3.2 px > 1 px");
  CHECK(r.record_count() == 36);
}

TEST_CASE("dump is canonical text with 17 significant digits and parses back losslessly") {
  const std::string dir = dynref::test::ScratchDir("trace_dump");
  dynref::test::WriteSampleTrace(dir + "/trace.dtr");
  DumpOptions o;
  o.frame = 1;
  o.entity = "mp7";
  const std::string csv = Dump(dir + "/trace.dtr", o);
  CHECK(csv.find("1,prob,mgd.temporal,map_point,mp7,0,after,0.27666666666666667\n") !=
        std::string::npos);
  CHECK(csv.find("1,residual,track.pose#1,,mp7@f1,0,start[2],0.001\n") != std::string::npos);
  CHECK(std::stod("0.27666666666666667") == 0.8 / 3.0 + 0.01);
  o.format = "jsonl";
  o.entity.clear();
  o.stage = "sgdo.epipolar";
  CHECK(Dump(dir + "/trace.dtr", o) ==
        "{\"frame\":1,\"type\":\"decision\",\"stage\":\"sgdo.epipolar\",\"kind\":\"feature\","
        "\"entity\":\"f1.2\",\"occurrence\":0,\"fields\":{\"kept\":\"0\",\"reason\":\"epipolar "
        "distance 3.2 px > 1 px\"}}\n");
}

TEST_CASE("two writes of the same records give byte-identical files and dumps", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("trace_determinism");
  dynref::test::WriteSampleTrace(dir + "/a.dtr");
  dynref::test::WriteSampleTrace(dir + "/b.dtr");
  CHECK(dynref::test::ReadFileBytes(dir + "/a.dtr") == dynref::test::ReadFileBytes(dir + "/b.dtr"));
  const auto a = dynref::test::RunDynref("trace dump '" + dir + "/a.dtr'");
  const auto b = dynref::test::RunDynref("trace dump '" + dir + "/b.dtr' --format csv");
  CHECK(a.exit_code == 0);
  CHECK(a.output == b.output);
  CHECK(a.output.size() > 1000);
}

TEST_CASE("level off writes nothing, frames level keeps only frame records") {
  const std::string dir = dynref::test::ScratchDir("trace_levels");
  {
    TraceWriter w(dir + "/off.dtr", Level::kOff, {});
    w.BeginFrame(0, 0.0);
    w.Decision("x", EntityKind::kFeature, "f0.1", true, "r");
    w.Close("complete");
  }
  CHECK(!std::ifstream(dir + "/off.dtr").good());
  {
    TraceWriter w(dir + "/frames.dtr", Level::kFrames, {});
    w.BeginFrame(0, 0.0);
    w.FrameCount("extract", "keypoints", 5);
    w.Decision("x", EntityKind::kFeature, "f0.1", true, "r");
    w.Close("complete");
  }
  TraceReader r(dir + "/frames.dtr");
  CHECK(r.level() == Level::kFrames);
  CHECK(r.record_count() == 2);
  {
    TraceWriter w(dir + "/abandoned.dtr", Level::kFull, {});
    w.BeginFrame(0, 0.0);
  }  // destroyed without Close(): nothing under the final name
  CHECK(!std::ifstream(dir + "/abandoned.dtr").good());
}

TEST_CASE("OBS associated_map_point_id is an exact field of the canonical view, after map_point_id") {
  const std::string dir = dynref::test::ScratchDir("trace_obs_associated");
  dynref::test::WriteSampleTrace(dir + "/trace.dtr");
  DumpOptions o;
  o.frame = 1;
  o.entity = "f1.2";
  const std::string csv = Dump(dir + "/trace.dtr", o);
  CHECK(csv.find("1,obs,,feature,f1.2,0,map_point_id,-1\n1,obs,,feature,f1.2,0,associated_map_point_id,20\n") !=
        std::string::npos);
  o.format = "jsonl";
  CHECK(Dump(dir + "/trace.dtr", o).find("\"map_point_id\":\"-1\",\"associated_map_point_id\":\"20\",\"u\"") !=
        std::string::npos);
}

TEST_CASE("schema 2 traces (no associated field) read with associated = map_point_id", "[cli]") {
  // tests/data/trace_v2: `dynref trace bench --frames 3 --features 6 --residuals 2` of dynref schema 2.
  const std::string v2 = dynref::test::SourcePath("tests/data/trace_v2/bench_schema2.dtr");
  TraceReader r(v2);
  CHECK(r.schema_version() == 2);
  REQUIRE(r.groups().size() == 3);
  int obs = 0;
  for (size_t g = 0; g < r.groups().size(); ++g)
    for (const Record& x : r.ReadGroup(g))
      if (x.type == RecordType::kObservation) {
        ++obs;
        CHECK(x.map_point_id == 7 * x.feature_index);
        CHECK(x.associated_map_point_id == x.map_point_id);
        CHECK(x.u == 100.5 + static_cast<double>(x.feature_index));  // the fields after it still line up
        CHECK(x.descriptor_hash == 0x9e3779b97f4a7c15ULL * static_cast<uint64_t>(x.feature_index));
      }
  CHECK(obs == 18);
  DumpOptions o;
  o.entity = "f1.3";
  CHECK(Dump(v2, o).find("1,obs,,feature,f1.3,0,associated_map_point_id,21\n") != std::string::npos);
  // The same bytes re-encoded by this writer (schema 3) diff as identical to the schema 2 file.
  const std::string dir = dynref::test::ScratchDir("trace_schema2_read");
  const auto replay = dynref::test::RunDynref("trace bench --replay '" + v2 + "' --out '" + dir + "/v3.dtr'");
  REQUIRE(replay.exit_code == 0);
  CHECK(TraceReader(dir + "/v3.dtr").schema_version() == 3);
  const auto d = dynref::test::RunDynref("diff '" + v2 + "' '" + dir + "/v3.dtr'");
  INFO(d.output);
  CHECK(d.exit_code == 0);
}

TEST_CASE("a schema 2 JSONL dump (no associated field) parses with associated = map_point_id") {
  const std::string line =
      "{\"frame\":4,\"type\":\"obs\",\"stage\":\"\",\"kind\":\"feature\",\"entity\":\"f4.2\",\"occurrence\":0,"
      "\"fields\":{\"map_point_id\":\"13\",\"u\":1.5,\"v\":2.5,\"depth_m\":0,\"octave\":\"1\","
      "\"descriptor_hash\":\"00000000000000ff\"}}";
  const FlatRecord f = ParseJsonlRecord(line, "x.jsonl", 1);
  REQUIRE(f.fields.size() == 7);
  CHECK(f.fields[1].name == "associated_map_point_id");
  CHECK(f.fields[1].exact);
  CHECK(f.fields[1].text == "13");
  CHECK(f.fields[2].name == "u");
}
