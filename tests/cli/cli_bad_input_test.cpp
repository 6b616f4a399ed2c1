// The dynref front end on bad input: unknown commands list the valid ones, `run` and
// `reproduce` check every argument before doing any work, messages name the option (exit 2).
#include <catch2/catch.hpp>

#include "test_support.h"

using dynref::test::ExpectBadInput;
using dynref::test::FileExists;
using dynref::test::Quote;
using dynref::test::RunDynref;
using dynref::test::ScratchDir;
using dynref::test::SourcePath;
using dynref::test::WriteText;

namespace {
const std::string kSeq = SourcePath("datasets/real/tum_fr1_desk_9frames");
}  // namespace

TEST_CASE("an unknown command is named and the valid ones listed", "[cli]") {
  const auto top = RunDynref("frobnicate");
  INFO(top.output);
  CHECK(top.exit_code == 2);
  CHECK(top.output.find("unknown command 'frobnicate' for 'dynref'") != std::string::npos);
  CHECK(top.output.find("eval") != std::string::npos);
  CHECK(top.output.find("reproduce") != std::string::npos);
  CHECK(top.output.find("A subcommand is required") == std::string::npos);
  const auto nested = RunDynref("trace frob run.dtr");
  CHECK(nested.exit_code == 2);
  CHECK(nested.output.find("unknown command 'frob' for 'dynref trace' (valid: dump, feature, verify, bench") !=
        std::string::npos);
  // No command at all still says one is required; --help still exits 0.
  const auto none = RunDynref("");
  CHECK(none.exit_code == 2);
  CHECK(none.output.find("subcommand is required") != std::string::npos);
  CHECK(RunDynref("--help").exit_code == 0);
  CHECK(RunDynref("trace --help").exit_code == 0);
}

TEST_CASE("run rejects an empty --frames, an unknown --detector and an --out that is a file", "[cli]") {
  const std::string dir = ScratchDir("cli_run_bad_args");
  const std::string seq = " --sequence " + Quote(kSeq) + " --camera tum_fr1";
  ExpectBadInput("run" + seq + " --out " + Quote(dir + "/r1") + " --frames ''", "--frames: empty value");
  CHECK_FALSE(FileExists(dir + "/r1"));
  ExpectBadInput("run" + seq + " --out " + Quote(dir + "/r2") + " --detector nosuch",
                 "--detector: unknown detection source 'nosuch'");
  ExpectBadInput("run" + seq + " --out " + Quote(dir + "/r2") + " --detector nanodet:x",
                 "--detector: source 'nanodet' takes no ':' argument");
  CHECK_FALSE(FileExists(dir + "/r2"));
  const std::string file = WriteText(dir + "/afile", "not a folder\n");
  ExpectBadInput("run" + seq + " --out " + Quote(file), "--out: " + file + " exists and is not a directory");
  ExpectBadInput("run" + seq + " --out " + Quote(file + "/sub"), "--out: " + file + " exists and is not a directory");
  const auto r = RunDynref("run" + seq + " --out " + Quote(file));
  CHECK(r.output.find("filesystem error") == std::string::npos);
}

TEST_CASE("reproduce sgdo-table6 checks every argument before synthesising anything", "[cli]") {
  const std::string dir = ScratchDir("cli_reproduce_bad_args");
  const std::string base0 = "reproduce sgdo-table6 --work " + Quote(dir + "/work") + " --out " +
                           Quote(dir + "/report.md");
  const std::string base = base0 + " --frames 30";
  ExpectBadInput(base + " --sequences static_xyz --sensitivity bogus", "--sensitivity: unknown preset 'bogus'");
  ExpectBadInput(base + " --sequences static_xyz --detections bogus", "--detections: unknown detection mode 'bogus'");
  ExpectBadInput(base + " --sequences static_xyz --detections none", "--detections: unknown detection mode 'none'");
  ExpectBadInput(base + " --sequences static_xyz,bogus", "--sequences: unknown preset 'bogus'");
  ExpectBadInput(base + " --sequences static_xyz,static_xyz", "--sequences: preset 'static_xyz' given twice");
  ExpectBadInput(base0 + " --sequences static_xyz --frames 10", "--frames: need at least 30 frames, got 10");
  ExpectBadInput(base + " --sequences static_xyz --seed -1", "--seed: must be an integer in 0..");
  const std::string file = WriteText(dir + "/afile", "x\n");
  ExpectBadInput("reproduce sgdo-table6 --sequences static_xyz --work " + Quote(file), "--work: " + file +
                 " exists and is not a directory");
  const auto r = RunDynref(base + " --sequences static_xyz --sensitivity bogus");
  CHECK(r.output.find("reproduce: synth") == std::string::npos);
  CHECK_FALSE(FileExists(dir + "/work"));  // nothing was synthesised or run
  CHECK_FALSE(FileExists(dir + "/report.md"));
}

TEST_CASE("reproduce blur-table1/3 check every argument before synthesising anything", "[cli]") {
  const std::string dir = ScratchDir("cli_reproduce_blur_bad_args");
  for (const std::string table : {"blur-table1", "blur-table3"}) {
    const std::string base = "reproduce " + table + " --work " + Quote(dir + "/work") + " --out " +
                             Quote(dir + "/report.md") + " --frames 30";
    ExpectBadInput(base + " --sequences static_xyz,bogus", "--sequences: unknown preset 'bogus'");
    ExpectBadInput(base + " --seeds 1,1", "--seeds: a seed is given twice");
    ExpectBadInput(base + " --seeds 1,x", "--seeds: must be an integer in 0..");
    ExpectBadInput(base + " --seeds 3-1", "--seeds: range '3-1' runs backwards");
    ExpectBadInput(base + " --seeds 1-3,2", "--seeds: a seed is given twice");
    ExpectBadInput(base + " --detections bogus", "--detections: unknown detection mode 'bogus'");
    ExpectBadInput("reproduce " + table + " --frames 10 --work " + Quote(dir + "/work"),
                   "--frames: need at least 30 frames, got 10");
  }
  ExpectBadInput("reproduce blur-table3 --frames 30 --work " + Quote(dir + "/work") + " --sweep walking_xyz,bogus",
                 "--sweep: unknown preset 'bogus'");
  CHECK_FALSE(FileExists(dir + "/work"));  // nothing was synthesised or run
  CHECK_FALSE(FileExists(dir + "/report.md"));
}
