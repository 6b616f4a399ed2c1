// `dynref trace dump|feature|bench` on bad input: exit 2 naming the option or the trace, and a
// note on stderr when a dump filter matches nothing (exit 0, see `trace dump --help`).
#include <catch2/catch.hpp>

#include "test_support.h"
#include "trace/trace_feature.h"
#include "trace_sample.h"

using dynref::test::ExpectBadInput;
using dynref::test::Quote;
using dynref::test::RunDynref;

namespace {
// RunDynref captures stdout and stderr together; these keep one of them (subshell redirection).
dynref::test::CommandResult StdoutOf(const std::string& args) {
  return dynref::test::RunShell("(" + Quote(dynref::test::DynrefExe()) + " " + args + " 2>/dev/null)");
}
dynref::test::CommandResult StderrOf(const std::string& args) {
  return dynref::test::RunShell("(" + Quote(dynref::test::DynrefExe()) + " " + args + " 2>&1 >/dev/null)");
}
}  // namespace

TEST_CASE("trace feature: a malformed id exits 2, an absent well-formed id exits 1", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("trace_cli_feature");
  const std::string trace = dir + "/a.dtr";
  dynref::test::WriteSampleTrace(trace);
  ExpectBadInput("trace feature " + Quote(trace) + " xyz", "id: 'xyz' is not an entity id");
  ExpectBadInput("trace feature " + Quote(trace) + " f1", "id: 'f1' is not an entity id");
  ExpectBadInput("trace feature " + Quote(trace) + " mp-3", "is not an entity id");
  const auto absent = RunDynref("trace feature " + Quote(trace) + " mp9999");
  CHECK(absent.exit_code == 1);  // documented: nothing mentions ID (ref/trace/README.md)
  CHECK(absent.output.find("no record of " + trace + " mentions mp9999") != std::string::npos);
  const auto ok = RunDynref("trace feature " + Quote(trace) + " f1.2");
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
  CHECK(ok.output.find("1,decision,sgdo.epipolar,feature,f1.2,0,") != std::string::npos);
}

TEST_CASE("trace: canonical entity ids") {
  using dynref::trace::IsCanonicalEntityId;
  for (const char* id : {"f0.3", "f42.17", "mp7", "kf3", "i2.1", "l0.5", "pl1.2", "r3.4", "mp7@f42", "mp17@kf3"})
    CHECK(IsCanonicalEntityId(id));
  for (const char* id : {"", "xyz", "f", "f1", "f1.", "f.1", "mp", "mpx", "mp1.2", "kf", "f1.2@", "mp7@x3",
                         "mp7@f", "f1.2x", "mp-1", "F1.2", " mp7"})
    CHECK_FALSE(IsCanonicalEntityId(id));
}

TEST_CASE("trace dump: a bad or absent --frame exits 2, an empty filter result notes it on stderr", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("trace_cli_dump");
  const std::string trace = dir + "/a.dtr";
  dynref::test::WriteSampleTrace(trace);  // frames 0..2, no records before the first frame
  ExpectBadInput("trace dump " + Quote(trace) + " --frame -2", "--frame: must be a frame index >= 0");
  ExpectBadInput("trace dump " + Quote(trace) + " --frame -1", trace + ": --frame -1: no such frame in this trace (frames 0..2)");
  ExpectBadInput("trace dump " + Quote(trace) + " --frame 3", trace + ": --frame 3: no such frame");
  const auto frame1 = RunDynref("trace dump " + Quote(trace) + " --frame 1");
  CHECK(frame1.exit_code == 0);
  CHECK(frame1.output.find("1,decision,sgdo.epipolar,feature,f1.2,0,kept,0") != std::string::npos);
  CHECK(frame1.output.find("note:") == std::string::npos);
  const auto stage = StderrOf("trace dump " + Quote(trace) + " --stage nosuch");
  CHECK(stage.exit_code == 0);
  CHECK(stage.output.find("dynref: note: no record of " + trace + " matched --stage nosuch") != std::string::npos);
  const auto entity = StdoutOf("trace dump " + Quote(trace) + " --entity nosuch --frame 0");
  CHECK(entity.exit_code == 0);
  CHECK(entity.output == "frame,type,stage,kind,entity,occurrence,field,value\n");  // stdout: header only
  const auto entity_err = StderrOf("trace dump " + Quote(trace) + " --entity nosuch --frame 0");
  CHECK(entity_err.output.find("matched --frame 0 --entity nosuch") != std::string::npos);
  CHECK(RunDynref("trace dump --help").output.find("Exit 0 also when the filters match no record") !=
        std::string::npos);
}

TEST_CASE("trace bench: non-positive sizes exit 2 naming the option", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("trace_cli_bench");
  const std::string out = " --out " + Quote(dir + "/b.dtr");
  ExpectBadInput("trace bench --frames -1" + out, "--frames: must be >= 1, got -1");
  ExpectBadInput("trace bench --frames 0" + out, "--frames: must be >= 1, got 0");
  ExpectBadInput("trace bench --features 0" + out, "--features: must be >= 1, got 0");
  ExpectBadInput("trace bench --residuals -5" + out, "--residuals: must be >= 0, got -5");
  CHECK_FALSE(dynref::test::FileExists(dir + "/b.dtr"));
  const auto ok = RunDynref("trace bench --frames 2 --features 10 --residuals 20" + out);
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
}
