// Overlays: deterministic pixels, golden PNG comparison, montage, CLI; feature plot.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <cstdlib>
#include <fstream>

#include "core/error.h"
#include "render/feature_plot.h"
#include "render/overlay.h"
#include "synthetic_run.h"
#include "test_support.h"
#include "trace/trace_feature.h"

using namespace dynref;

namespace {

// Pixels differing by more than 2/255 in some channel, and the image sizes agree.
long DifferingPixels(const std::string& a, const std::string& b) {
  OIIO::ImageBuf A(a), B(b);
  if (!A.read() || !B.read()) return -1;
  if (A.spec().width != B.spec().width || A.spec().height != B.spec().height) return -1;
  const auto r = OIIO::ImageBufAlgo::compare(A, B, 2.5f / 255.0f, 2.5f / 255.0f);
  return static_cast<long>(r.nfail);
}

}  // namespace

TEST_CASE("golden overlay of a synthetic frame with GT labels matches golden/overlay_synthetic_gt.png") {
  const std::string dir = test::ScratchDir("render_golden");
  const test::SyntheticRun run = test::MakeSyntheticRun(dir);
  render::OverlayOptions o;
  o.gt = true;
  o.out_dir = dir + "/out";
  const auto written = render::RenderRunOverlays(run.run, 0, 1, o);
  REQUIRE(written.size() == 2);
  const std::string golden = test::SourcePath("golden/overlay_synthetic_gt.png");
  if (const char* update = std::getenv("DYNREF_UPDATE_GOLDEN"); update && std::string(update) == "1") {
    REQUIRE(std::filesystem::copy_file(written[0], golden,
                                       std::filesystem::copy_options::overwrite_existing));
    // Update mode never passes: the new golden must be committed and compared by a normal run.
    FAIL("golden updated: " << golden << "; rerun without DYNREF_UPDATE_GOLDEN to compare");
  }
  // Threshold: at most 0.1 % of the pixels may differ by more than 2/255 (PNG codecs and
  // image decoders of another platform; our own drawing is integer-exact).
  const long diff = DifferingPixels(written[0], golden);
  INFO("rendered " << written[0] << " vs " << golden);
  CHECK(diff >= 0);
  CHECK(diff <= 640 * 480 / 1000);
}

TEST_CASE("overlay pixels are identical across two renders, montage tiles the frames", "[cli]") {
  const std::string dir = test::ScratchDir("render_determinism");
  const test::SyntheticRun run = test::MakeSyntheticRun(dir);
  render::OverlayOptions o;
  o.out_dir = dir + "/a";
  o.montage_path = dir + "/montage.png";
  o.montage_columns = 2;
  const auto a = render::RenderRunOverlays(run.run, 0, 1, o);
  o.out_dir = dir + "/b";
  o.montage_path.clear();
  const auto b = render::RenderRunOverlays(run.run, 0, 1, o);
  REQUIRE(a.size() == 3);
  CHECK(DifferingPixels(a[0], b[0]) == 0);
  CHECK(DifferingPixels(a[1], b[1]) == 0);
  OIIO::ImageBuf m(dir + "/montage.png");
  REQUIRE(m.read());
  CHECK(m.spec().width == 2 * 640 + 3 * 4);
  CHECK(m.spec().height == 480 + 2 * 4);
  // Each tile holds its own frame's pixels (tiles are moved into the montage).
  OIIO::ImageBuf f0(a[0]), f1(a[1]);
  REQUIRE(f0.read());
  REQUIRE(f1.read());
  int mismatches = 0;
  for (int y = 0; y < 480; y += 37)
    for (int x = 0; x < 640; x += 41)
      for (int ch = 0; ch < 3; ++ch) {
        mismatches += m.getchannel(4 + x, 4 + y, 0, ch) != f0.getchannel(x, y, 0, ch);
        mismatches += m.getchannel(8 + 640 + x, 4 + y, 0, ch) != f1.getchannel(x, y, 0, ch);
      }
  CHECK(mismatches == 0);
}

TEST_CASE("overlay data: probabilities, decisions, shapes and instance states come from the trace") {
  const std::string dir = test::ScratchDir("render_data");
  const test::SyntheticRun run = test::MakeSyntheticRun(dir);
  trace::TraceReader reader(run.run + "/trace.dtr");
  const auto frames = render::CollectOverlayFrames(reader, 1, 1);
  REQUIRE(frames.size() == 1);
  const render::OverlayFrame& f = frames[0];
  CHECK(f.frame == 1);
  CHECK(f.features.size() == 48);
  CHECK(f.features[3].decision == 0);   // the planted false positive
  CHECK(!f.features[45].has_prob);
  CHECK(f.features[2].decision == -1);  // undecided
  REQUIRE(f.shapes.size() == 3);
  CHECK(f.shapes[0].x1 == 380);
  CHECK(f.shapes[1].decision == 0);
  CHECK(f.instances.at(1).prob == 0.93);
  CHECK(f.counts.at(1).first == "sgdo.epipolar.rejected");
}

TEST_CASE("dynref overlay CLI writes PNGs and rejects a bad frame range", "[cli]") {
  const std::string dir = test::ScratchDir("render_cli");
  const test::SyntheticRun run = test::MakeSyntheticRun(dir);
  const auto ok = test::RunDynref("overlay '" + run.run + "' --frames 0-1 --gt --montage '" + dir +
                                  "/m.png'");
  CHECK(ok.exit_code == 0);
  CHECK(std::ifstream(run.run + "/overlays/overlay_000001.png").good());
  CHECK(std::ifstream(dir + "/m.png").good());
  // A montage inside the not yet existing --out folder (it used to fail: "cannot open ... for writing").
  CHECK(test::RunDynref("overlay '" + run.run + "' --frames 0-1 --out '" + dir + "/new' --montage '" + dir +
                        "/new/m.png'").exit_code == 0);
  CHECK(std::ifstream(dir + "/new/m.png").good());
  CHECK(std::ifstream(dir + "/new/overlay_000000.png").good());
  CHECK(test::RunDynref("overlay '" + run.run + "' --frames 5-2").exit_code == 2);
  CHECK(test::RunDynref("overlay '" + run.run + "' --frames 7-9").exit_code == 2);
}

TEST_CASE("feature history and plot of one feature", "[cli]") {
  const std::string dir = test::ScratchDir("render_feature_plot");
  const test::SyntheticRun run = test::MakeSyntheticRun(dir);
  trace::TraceReader reader(run.run + "/trace.dtr");
  const trace::FeatureHistory h = trace::CollectFeatureHistory(reader, "mp103");
  // mp103 = feature index 3 in both frames: obs + prob + decision per frame.
  REQUIRE(h.rows.size() == 6);
  CHECK(h.rows[0].entity == "f0.3");
  const render::Canvas plot = render::RenderFeaturePlot(h);
  CHECK(plot.width() == 900);
  const auto cli = test::RunDynref("trace feature '" + run.run + "' f1.3 --plot '" + dir + "/p.png'");
  CHECK(cli.exit_code == 0);
  CHECK(cli.output.find("1,decision,sgdo.epipolar,feature,f1.3,0,kept=0 reason=dynamic") !=
        std::string::npos);
  CHECK(test::RunDynref("trace feature '" + run.run + "' mp9999").exit_code == 1);
}

TEST_CASE("dynref overlay leaves no partial output when a frame fails or the range is bad", "[cli]") {
  const std::string dir = test::ScratchDir("render_no_partial");
  const test::SyntheticRun run = test::MakeSyntheticRun(dir);
  // Truncate the RGB PNG of frame 1: frame 0 renders fine, frame 1 cannot be read.
  const std::string rgb1 = run.sequence + "/rgb/1.033333.png";
  const std::string bytes = test::ReadFileBytes(rgb1);
  REQUIRE(bytes.size() > 200);
  std::ofstream(rgb1, std::ios::binary | std::ios::trunc) << bytes.substr(0, 200);
  const std::string out = dir + "/out/ov";
  const auto r = test::RunDynref("overlay " + test::Quote(run.run) + " --frames 0-1 --out " + test::Quote(out) +
                                 " --montage " + test::Quote(dir + "/m.png"));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("1.033333.png") != std::string::npos);
  // A range reaching past the traced frames is an error, not silently clipped (issue 20 item 11).
  const auto past = test::RunDynref("overlay " + test::Quote(run.run) + " --frames 1-5 --out " + test::Quote(out));
  CHECK(past.exit_code == 2);
  CHECK(past.output.find("is not inside the run's traced frames") != std::string::npos);
  CHECK(!test::FileExists(out + "/overlay_000000.png"));
  CHECK(!test::FileExists(out));
  CHECK(!test::FileExists(dir + "/out"));  // the parent it created for its temp folder is gone too
  CHECK(!test::FileExists(dir + "/m.png"));
  // Default output folder RUN/overlays: not created either.
  const auto d = test::RunDynref("overlay " + test::Quote(run.run) + " --frames 0-1");
  CHECK(d.exit_code == 2);
  CHECK(!test::FileExists(run.run + "/overlays"));
  // Nothing left next to the run (no temp folders).
  int entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(run.run)) {
    INFO(e.path().string());
    CHECK(e.path().filename().string().find(".tmp.") == std::string::npos);
    ++entries;
  }
  CHECK(entries > 0);
  // Bad ranges are rejected before any folder is created.
  std::ofstream(rgb1, std::ios::binary | std::ios::trunc) << bytes;
  for (const std::string frames : {"7-9", "5-2", "x"}) {
    INFO(frames);
    CHECK(test::RunDynref("overlay " + test::Quote(run.run) + " --frames " + frames + " --out " +
                          test::Quote(dir + "/bad")).exit_code == 2);
    CHECK(!test::FileExists(dir + "/bad"));
  }
  // Re-rendering into an existing folder keeps its other files and replaces the overlays.
  REQUIRE(test::RunShell("mkdir -p " + test::Quote(dir + "/keep") + " && echo mine > " +
                         test::Quote(dir + "/keep/notes.txt")).exit_code == 0);
  const auto ok = test::RunDynref("overlay " + test::Quote(run.run) + " --frames 0-1 --out " + test::Quote(dir + "/keep"));
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
  CHECK(test::FileExists(dir + "/keep/overlay_000000.png"));
  CHECK(test::FileExists(dir + "/keep/overlay_000001.png"));
  CHECK(test::FileExists(dir + "/keep/notes.txt"));
}

TEST_CASE("dynref overlay rejects --montage-columns below 1", "[cli]") {
  const std::string dir = test::ScratchDir("render_montage_columns");
  const test::SyntheticRun run = test::MakeSyntheticRun(dir);
  for (const std::string cols : {"0", "-3"}) {
    INFO(cols);
    test::ExpectBadInput("overlay " + test::Quote(run.run) + " --frames 0-1 --out " + test::Quote(dir + "/ov") +
                             " --montage " + test::Quote(dir + "/m.png") + " --montage-columns " + cols,
                         "--montage-columns");
    CHECK(!test::FileExists(dir + "/ov"));
    CHECK(!test::FileExists(dir + "/m.png"));
  }
  render::OverlayOptions o;
  o.out_dir = dir + "/lib";
  o.montage_columns = 0;
  CHECK_THROWS_AS(render::RenderRunOverlays(run.run, 0, 1, o), InputError);
  CHECK(!test::FileExists(dir + "/lib"));
}
