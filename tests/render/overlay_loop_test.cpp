// Overlays mark a loop-closure keyframe (issue 34): the frame whose trace holds PROB
// loop.transform on kf<N> gets a magenta border and a "LOOP" banner; other frames do not.
#include <OpenImageIO/imagebuf.h>

#include <catch2/catch.hpp>
#include <string>

#include "core/atomic_file.h"
#include "render/overlay.h"
#include "synthetic_run.h"
#include "test_support.h"
#include "trace/trace_writer.h"

using namespace dynref;

namespace {

// The synthetic sequence of MakeSyntheticRun with a second run whose frame 1 closes a loop
// (keyframe 7 onto keyframe 0), written as ref/loop/loop_closer.cpp writes it.
std::string MakeLoopRun(const std::string& dir) {
  const test::SyntheticRun base = test::MakeSyntheticRun(dir);
  const std::string run = dir + "/loop_run";
  std::system(("mkdir -p '" + run + "'").c_str());
  AtomicWriteFile(run + "/run.json", "{\n  \"sequence\": \"" + base.sequence + "\",\n  \"method\": \"orb\"\n}\n");
  trace::RunHeader h;
  h.method = "orb";
  h.sequence_path = base.sequence;
  trace::TraceWriter w(run + "/trace.dtr", trace::Level::kFull, h);
  for (int f = 0; f < 2; ++f) {
    w.BeginFrame(f, f == 0 ? 1.0 : 1.033333);
    w.Observation(0, 100, 320.5, 240.5, 1.0, 0, 0x9e3779b97f4a7c15ULL);
    if (f == 1) {
      w.ProbabilityUpdate("loop.transform", trace::EntityKind::kKeyFrame, "kf7",
                          {{"loop_kf", 0}, {"tx", 0.01}, {"ty", 0}, {"tz", 0}, {"qx", 0}, {"qy", 0}, {"qz", 0},
                           {"qw", 1}, {"moved_m", 0.0123}},
                          0, 0);
      w.FrameCount("loop", "closed", 1);
    }
  }
  w.Close("complete");
  return run;
}

bool IsLoopColour(const OIIO::ImageBuf& b, int x, int y) {
  return b.getchannel(x, y, 0, 0) > 0.99f && b.getchannel(x, y, 0, 1) < 0.01f && b.getchannel(x, y, 0, 2) > 0.99f;
}

}  // namespace

TEST_CASE("overlay data: a loop.transform record becomes the frame's loop, other frames have none") {
  const std::string dir = test::ScratchDir("render_loop_data");
  const std::string run = MakeLoopRun(dir);
  trace::TraceReader reader(run + "/trace.dtr");
  const auto frames = render::CollectOverlayFrames(reader, 0, 1);
  REQUIRE(frames.size() == 2);
  CHECK(frames[0].loops.empty());
  REQUIRE(frames[1].loops.size() == 1);
  CHECK(frames[1].loops[0].keyframe == 7);
  CHECK(frames[1].loops[0].loop_keyframe == 0);
  CHECK(frames[1].loops[0].moved_m == 0.0123);
}

TEST_CASE("overlay of a loop-closure keyframe has a magenta border, an ordinary frame has not", "[cli]") {
  const std::string dir = test::ScratchDir("render_loop_pixels");
  const std::string run = MakeLoopRun(dir);
  render::OverlayOptions o;
  o.out_dir = dir + "/out";
  const auto written = render::RenderRunOverlays(run, 0, 1, o);
  REQUIRE(written.size() == 2);
  OIIO::ImageBuf plain(written[0]), loop(written[1]);
  REQUIRE(plain.read());
  REQUIRE(loop.read());
  // Border pixels on all four sides (the text panel covers the top left, the legend the bottom right).
  for (const auto& [x, y] : {std::pair{320, 2}, std::pair{2, 300}, std::pair{637, 200}, std::pair{320, 477}}) {
    INFO("pixel " << x << "," << y);
    CHECK(IsLoopColour(loop, x, y));
    CHECK(!IsLoopColour(plain, x, y));
  }
  // The banner's text (magenta glyphs) above the bottom border, left side.
  int banner = 0;
  for (int y = 430; y < 470; ++y)
    for (int x = 14; x < 300; ++x) banner += IsLoopColour(loop, x, y) && !IsLoopColour(plain, x, y);
  CHECK(banner > 100);
}
