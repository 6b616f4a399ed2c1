// ref/trace/external/dynref_trace.hpp (the dependency-free C++17 writer for outside code): every
// record of dynref's own golden traces re-emitted through it gives a trace `dynref diff` finds
// identical, and in fact the same bytes; an unfinished writer leaves no file.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

#include "test_support.h"
#include "trace/external/dynref_trace.hpp"
#include "trace/trace_reader.h"
#include "trace_sample.h"

namespace {

std::string Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void Reemit(const std::string& source, const std::string& out) {
  using namespace dynref;
  trace::TraceReader r(source);
  dynref_trace::Writer w(out, r.level() == trace::Level::kFull ? dynref_trace::Level::kFull : dynref_trace::Level::kFrames,
                         r.header());
  for (size_t g = 0; g < r.groups().size(); ++g)
    for (const trace::Record& x : r.ReadGroup(g)) {
      const auto kind = dynref_trace::Kind(static_cast<uint8_t>(x.kind));
      switch (x.type) {
        case trace::RecordType::kFrame: w.Frame(x.frame, x.timestamp); break;
        case trace::RecordType::kPose: w.Pose(x.name, x.T_wc); break;
        case trace::RecordType::kCount: w.Count(x.stage, x.name, x.value); break;
        case trace::RecordType::kObservation:
          w.Obs(x.feature_index, x.map_point_id, x.associated_map_point_id, x.u, x.v, x.depth_m, x.octave,
                x.descriptor_hash);
          break;
        case trace::RecordType::kProbability: {
          std::vector<std::pair<std::string, double>> in;
          for (const trace::NamedValue& nv : x.inputs) in.emplace_back(nv.name, nv.value);
          w.Prob(x.stage, kind, x.entity, in, x.before, x.after);
          break;
        }
        case trace::RecordType::kResidual:
          w.Residual(x.stage, x.residual_kind, x.entity, x.residual_start, x.residual_end, x.information, x.weight,
                     x.robust_loss, x.chi2, x.inlier);
          break;
        case trace::RecordType::kDecision: w.Decision(x.stage, kind, x.entity, x.kept, x.reason); break;
      }
    }
  w.Close(r.end_state());
}

}  // namespace

// Goldens may be of an older schema until they are regenerated: the re-emitted trace (this
// schema) must diff identical always, and be the same bytes when the source is of this schema.
TEST_CASE("external C++17 writer: golden traces re-emitted diff identical (same bytes when of this schema)", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("trace_external_writer");
  for (const std::string golden : {"golden/orb_30f/trace.dtr", "golden/sgdo_30f/trace.dtr", "golden/blur_30f/trace.dtr"}) {
    INFO(golden);
    const std::string src = dynref::test::SourcePath(golden);
    const std::string out = dir + "/" + std::to_string(std::hash<std::string>()(golden)) + ".dtr";
    Reemit(src, out);
    const dynref::test::CommandResult d = dynref::test::RunDynref("diff " + src + " " + out);
    INFO(d.output);
    CHECK(d.exit_code == 0);
    CHECK(dynref::trace::TraceReader(out).schema_version() == dynref_trace::kSchemaVersion);
    if (dynref::trace::TraceReader(src).schema_version() == dynref::trace::kSchemaVersion) CHECK(Bytes(out) == Bytes(src));
  }
}

TEST_CASE("external C++17 writer: a fresh trace re-emitted is the same bytes (schema 3 OBS included)") {
  const std::string dir = dynref::test::ScratchDir("trace_external_fresh");
  dynref::test::WriteSampleTrace(dir + "/a.dtr");  // f<frame>.2: map_point_id -1, associated 20
  Reemit(dir + "/a.dtr", dir + "/b.dtr");
  CHECK(Bytes(dir + "/b.dtr") == Bytes(dir + "/a.dtr"));
  CHECK(dynref_trace::kSchemaVersion == static_cast<uint32_t>(dynref::trace::kSchemaVersion));
  CHECK(dynref::trace::TraceReader(dir + "/b.dtr").ReadGroup(1).at(5).associated_map_point_id == 20);
}

TEST_CASE("external C++17 writer end to end: a fresh mgd run's trace re-emitted is the same bytes", "[cli]") {
  using dynref::test::Quote;
  const std::string dir = dynref::test::ScratchDir("trace_external_run");
  REQUIRE(dynref::test::RunDynref("synth --preset walking_xyz --seed 1 --frames 8 --detections yolo-like --out " +
                                  Quote(dir + "/seq")).exit_code == 0);
  const auto run = dynref::test::RunDynref("run --method mgd --sequence " + Quote(dir + "/seq") + " --detections " +
                                           Quote(dir + "/seq/detections/yolo-like") + " --out " + Quote(dir + "/run") +
                                           " --trace full --no-progress");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  Reemit(dir + "/run/trace.dtr", dir + "/b.dtr");
  CHECK(Bytes(dir + "/b.dtr") == Bytes(dir + "/run/trace.dtr"));
}

TEST_CASE("external C++17 writer: a small hand-written trace reads back, an unclosed one leaves no file") {
  const std::string dir = dynref::test::ScratchDir("trace_external_small");
  {
    dynref_trace::Writer w(dir + "/t.dtr", dynref_trace::Level::kFull, {{"method", "outside"}});
    w.Count("setup", "cameras", 1);  // before the first frame: group -1
    w.Frame(0, 100.5);
    w.Prob("my.stage", dynref_trace::Kind::kFeature, "f0.3", {{"d_px", 0.25}}, 0.0, 0.75);
    w.Decision("my.stage", dynref_trace::Kind::kFeature, "f0.3", false, "too-far");
    w.Frame(1, 100.6);
    w.Pose("final", {1, 0, 0, 0.1, 0, 1, 0, 0.2, 0, 0, 1, 0.3});
    w.Close();
  }
  dynref::trace::TraceReader r(dir + "/t.dtr");
  CHECK(r.HeaderValue("method") == "outside");
  CHECK(r.record_count() == 6);
  REQUIRE(r.groups().size() == 3);
  CHECK(r.groups()[0].frame == -1);
  const auto g1 = r.ReadGroup(1);
  REQUIRE(g1.size() == 3);
  CHECK(g1[1].after == 0.75);
  CHECK(g1[1].inputs[0].name == "d_px");
  CHECK(g1[2].reason == "too-far");
  CHECK(r.ReadGroup(2)[1].T_wc[11] == 0.3);
  {
    dynref_trace::Writer w(dir + "/unfinished.dtr", dynref_trace::Level::kFrames, {});
    w.Frame(0, 1.0);
  }  // destroyed without Close
  CHECK_FALSE(dynref::test::FileExists(dir + "/unfinished.dtr"));
  CHECK_FALSE(dynref::test::FileExists(dir + "/unfinished.dtr.tmp"));
}
