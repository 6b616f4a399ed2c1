// `reproduce --collect` (Workspace in WorkMode::kCollect) reads sequences made by `dynref synth`:
// their synth.yaml must state the table's arguments, including the full image size (issue 37:
// `synth --width` writes a `width:` line, and a 160 px smoke sequence must not pass for a table's).
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "reproduce/arg_checks.h"
#include "reproduce/workspace.h"
#include "test_support.h"

using namespace dynref;

namespace {

// <work>/seq/walking_xyz as `dynref synth --preset walking_xyz --frames 30 --seed 1 --detections
// ideal` writes it (the files --collect reads), plus `extra` lines in synth.yaml.
std::string CollectSynthFolder(const std::string& work, const std::string& extra) {
  const std::string seq = work + "/seq/walking_xyz";
  std::filesystem::create_directories(seq + "/detections/ideal");
  test::WriteText(seq + "/synth.yaml",
                  "# dynref synth parameters\ngenerator: dynref test\npreset: walking_xyz\nframes: 30\nseed: 1\n"
                  "blur: false\nlow_light: false\ndetections: ideal\n" + extra);
  return seq;
}

reproduce::SynthSpec CollectSpec() {
  reproduce::SynthSpec spec;
  spec.frames = 30;
  spec.seed = 1;
  spec.detections = "ideal";
  return spec;
}

}  // namespace

TEST_CASE("reproduce --collect refuses a sequence synthesised with --width below full size, naming synth.yaml") {
  const std::string dir = test::ScratchDir("reproduce_collect_width");
  SECTION("no width line (full size): accepted") {
    const std::string seq = CollectSynthFolder(dir, "");
    reproduce::Workspace ws(dir, CollectSpec(), false, reproduce::WorkMode::kCollect);
    CHECK(ws.EnsureSequence("walking_xyz") == seq);
  }
  SECTION("width: 640 (the camera's own width): accepted") {
    const std::string seq = CollectSynthFolder(dir, "width: 640\nheight: 480\n");
    reproduce::Workspace ws(dir, CollectSpec(), false, reproduce::WorkMode::kCollect);
    CHECK(ws.EnsureSequence("walking_xyz") == seq);
  }
  SECTION("width: 160: InputError naming synth.yaml and both widths") {
    const std::string seq = CollectSynthFolder(dir, "width: 160\nheight: 120\n");
    reproduce::Workspace ws(dir, CollectSpec(), false, reproduce::WorkMode::kCollect);
    try {
      ws.EnsureSequence("walking_xyz");
      FAIL("a 160 px sequence was collected");
    } catch (const InputError& e) {
      CHECK(e.file() == seq + "/synth.yaml");
      CHECK_THAT(e.what(), Catch::Contains("width is '160', this table needs '640'"));
    }
  }
}

TEST_CASE("reproduce --frames 0: every preset at its own length (the real sequence's), checked on --collect") {
  reproduce::SynthSpec paper;
  paper.frames = 0;
  CHECK(reproduce::FramesOf(paper, "walking_xyz") == 859);  // fr3/walking_xyz
  CHECK(reproduce::FramesOf(paper, "sitting_static") == 707);
  CHECK(reproduce::FramesOf(CollectSpec(), "walking_xyz") == 30);
  CHECK_NOTHROW(reproduce::CheckMatrixArgs(0, {1}, "yolo-like", {"walking_xyz"}, false, false));
  CHECK_THROWS_AS(reproduce::CheckMatrixArgs(29, {1}, "yolo-like", {"walking_xyz"}, false, false), InputError);
  const std::string table = reproduce::FramesTable({"walking_xyz", "sitting_static"}, 0, {"w_xyz", "s_static"});
  CHECK_THAT(table, Catch::Contains("| walking_xyz | 859 | w_xyz | 859 |"));
  CHECK_THAT(table, Catch::Contains("| sitting_static | 707 | s_static | 707 |"));
  // A 30-frame sequence is not the 859 frames --frames 0 asks for.
  const std::string dir = test::ScratchDir("reproduce_collect_frames0");
  const std::string seq = CollectSynthFolder(dir, "");
  reproduce::SynthSpec spec = CollectSpec();
  spec.frames = 0;
  reproduce::Workspace ws(dir, spec, false, reproduce::WorkMode::kCollect);
  try {
    ws.EnsureSequence("walking_xyz");
    FAIL("a 30-frame sequence was collected for --frames 0");
  } catch (const InputError& e) {
    CHECK(e.file() == seq + "/synth.yaml");
    CHECK_THAT(e.what(), Catch::Contains("frames is '30', this table needs '859'"));
  }
}
