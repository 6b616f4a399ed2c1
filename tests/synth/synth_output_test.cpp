// dynref synth: TUM layout, determinism, every preset, CLI exit codes (issue 3).
#include <catch2/catch.hpp>

#include <dirent.h>
#include <sys/stat.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "synth/synth.h"
#include "synth/world.h"
#include "test_support.h"
#include "io/image_file.h"

namespace {

using dynref::synth::GenerateSequence;
using dynref::synth::SynthOptions;

// Every regular file under dir (relative path -> bytes).
void ReadTree(const std::string& root, const std::string& rel, std::map<std::string, std::string>* out) {
  DIR* d = ::opendir((root + "/" + rel).c_str());
  REQUIRE(d != nullptr);
  while (dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name == "." || name == "..") continue;
    const std::string r = rel.empty() ? name : rel + "/" + name;
    struct stat st {};
    ::stat((root + "/" + r).c_str(), &st);
    if (S_ISDIR(st.st_mode)) {
      ReadTree(root, r, out);
    } else {
      std::ifstream in(root + "/" + r, std::ios::binary);
      std::ostringstream s;
      s << in.rdbuf();
      (*out)[r] = s.str();
    }
  }
  ::closedir(d);
}

SynthOptions Options(const std::string& preset, int frames, const std::string& out) {
  SynthOptions o;
  o.preset = preset, o.frames = frames, o.out = out;
  return o;
}

}  // namespace

TEST_CASE("synth: same arguments give byte-identical folders with blur and low light and all detections", "[e2e]") {
  const std::string a = dynref::test::ScratchDir("synth_det_a"), b = dynref::test::ScratchDir("synth_det_b");
  SynthOptions o = Options("sitting_static", 3, a);
  o.blur = true, o.low_light = true, o.detections = "all", o.blur_subframes = 3;
  GenerateSequence(o);
  o.out = b;
  GenerateSequence(o);
  std::map<std::string, std::string> ta, tb;
  ReadTree(a, "", &ta);
  ReadTree(b, "", &tb);
  CHECK(ta.size() > 30);
  REQUIRE(ta.size() == tb.size());
  for (const auto& [path, bytes] : ta) {
    INFO(path);
    REQUIRE(tb.count(path) == 1);
    CHECK(tb[path] == bytes);
    CHECK(path.find(".tmp.") == std::string::npos);  // no temp file left behind
  }
  // A different seed changes the images.
  const std::string c = dynref::test::ScratchDir("synth_det_c");
  o.out = c, o.seed = 2;
  GenerateSequence(o);
  std::map<std::string, std::string> tc;
  ReadTree(c, "", &tc);
  // First rgb/*.png of each tree (keys sorted, stamps may differ between seeds).
  const auto first_png = [](const std::map<std::string, std::string>& tree) {
    const auto it = tree.lower_bound("rgb/");
    return it != tree.end() && it->first.rfind("rgb/", 0) == 0 ? it->second : std::string();
  };
  const std::string png_a = first_png(ta), png_c = first_png(tc);
  REQUIRE(!png_a.empty());
  REQUIRE(!png_c.empty());
  CHECK(png_c != png_a);
}

TEST_CASE("synth: TUM layout read by OpenSequence with GT for every frame and camera.yaml") {
  const std::string dir = dynref::test::ScratchDir("synth_layout");
  GenerateSequence(Options("walking_xyz", 4, dir));
  const dynref::Sequence seq = dynref::OpenSequence(dir);
  REQUIRE(seq.frames.size() == 4);
  CHECK(seq.rgb_count == 4);
  CHECK(seq.depth_count == 4);
  REQUIRE(seq.groundtruth.size() == 4);
  CHECK(seq.camera.fx == Approx(535.4));
  CHECK(seq.camera.cy == Approx(247.6));
  CHECK(seq.camera.width == 640);
  for (size_t i = 0; i < seq.frames.size(); ++i) {
    const auto& f = seq.frames[i];
    const double dt = f.depth_stamp - f.rgb_stamp;
    CHECK(dt > 0.0004);  // depth logged 0.5..3 ms after rgb, like a Kinect log
    CHECK(dt < 0.0031);
    CHECK(std::abs(seq.groundtruth[i].stamp - f.rgb_stamp) < 1e-6);
    const cv::Mat rgb = dynref::LoadRgb(seq, f);
    const cv::Mat depth = dynref::LoadDepthMeters(seq, f);
    CHECK(rgb.size() == cv::Size(640, 480));
    CHECK(depth.size() == cv::Size(640, 480));
    double max_z = 0;
    cv::minMaxLoc(depth, nullptr, &max_z);
    CHECK(max_z <= 4.5);
  }
  const dynref::DetectionsReader gt(dir + "/gt");
  CHECK(gt.source() == "gt");
  CHECK(gt.Stamps().size() == 4);
  for (const auto& f : seq.frames) CHECK(gt.Has(f.rgb_stamp_text));
  std::ifstream labels(dir + "/gt/labels.yaml"), moving(dir + "/gt/moving.txt");
  std::stringstream ls, ms;
  ls << labels.rdbuf();
  ms << moving.rdbuf();
  CHECK(ls.str().find("1: {class_name: person, coco_id: 0, prior_dynamic: true}") != std::string::npos);
  CHECK(ls.str().find("20: {class_name: chair, coco_id: 56, prior_dynamic: false}") != std::string::npos);
  CHECK(ms.str().find(seq.frames[1].rgb_stamp_text + " 1 2") != std::string::npos);
}

TEST_CASE("synth: every preset generates and has people only where expected", "[e2e]") {
  CHECK(dynref::synth::PresetNames().size() == 18);  // the presets table of datasets/README.md
  for (const std::string& preset : dynref::synth::PresetNames()) {
    INFO(preset);
    const std::string dir = dynref::test::ScratchDir("synth_preset_" + preset);
    GenerateSequence(Options(preset, 2, dir));
    const dynref::Sequence seq = dynref::OpenSequence(dir);
    CHECK(seq.frames.size() == 2);
    std::ifstream labels(dir + "/gt/labels.yaml");
    std::stringstream ls;
    ls << labels.rdbuf();
    const bool has_person = ls.str().find("class_name: person") != std::string::npos;
    CHECK(has_person == (preset.rfind("static_", 0) != 0 && preset != "loop_static"));
    if (preset == "moving_box") CHECK(ls.str().find("class_name: box, coco_id: -1") != std::string::npos);
  }
  CHECK_THROWS_AS(dynref::synth::GetPreset("walking_sideways"), dynref::InputError);
}

TEST_CASE("synth: CLI writes a sequence that dynref info reads and bad arguments exit 2", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("synth_cli");
  const auto r = dynref::test::RunDynref("synth --preset walking_xyz --frames 3 --out '" + dir + "/wx'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto info = dynref::test::RunDynref("info '" + dir + "/wx'");
  INFO(info.output);
  CHECK(info.exit_code == 0);
  CHECK(info.output.find("3 RGB-D pairs") != std::string::npos);
  CHECK(info.output.find("GT coverage    3 of 3") != std::string::npos);
  // The share of moving pixels per frame, from SEQ/gt (people walk in every frame of walking_xyz).
  CHECK(info.output.find("moving pixels  ") != std::string::npos);
  CHECK(info.output.find("3 of 3 labelled frames show motion") != std::string::npos);
  CHECK(dynref::test::RunDynref("synth --preset nope --out '" + dir + "/x'").exit_code == 2);
  CHECK(dynref::test::RunDynref("synth --preset walking_xyz --detections magic --out '" + dir + "/y'").exit_code == 2);
  CHECK(dynref::test::RunDynref("synth --preset walking_xyz --frames -1 --out '" + dir + "/z'").exit_code == 2);
  const auto m = dynref::test::RunDynref("synth-montage '" + dir + "/wx' --frames-per-row 2 --out '" + dir + "/m.png'");
  INFO(m.output);
  CHECK(m.exit_code == 0);
  CHECK(!dynref::ImageRead(dir + "/m.png").empty());
}

namespace {

// Names of the entries of dir (not recursive), or empty when dir cannot be opened.
std::vector<std::string> Entries(const std::string& dir) {
  std::vector<std::string> names;
  DIR* d = ::opendir(dir.c_str());
  if (!d) return names;
  while (dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name != "." && name != "..") names.push_back(name);
  }
  ::closedir(d);
  return names;
}

}  // namespace

TEST_CASE("synth replaces an earlier synth output as a whole and leaves no temp folder") {
  const std::string dir = dynref::test::ScratchDir("synth_replace");
  const std::string out = dir + "/seq";
  GenerateSequence(Options("walking_xyz", 5, out));
  REQUIRE(Entries(out + "/rgb").size() == 5);
  // Same folder, fewer frames (and the trailing-slash spelling): no stale frames of the first run.
  GenerateSequence(Options("walking_xyz", 2, out + "/"));
  CHECK(Entries(out + "/rgb").size() == 2);
  CHECK(Entries(out + "/depth").size() == 2);
  CHECK(Entries(out + "/gt/motion").size() == 2);
  const dynref::Sequence seq = dynref::OpenSequence(out);
  CHECK(seq.frames.size() == 2);
  CHECK(dynref::DetectionsReader(out + "/gt").Stamps().size() == 2);
  // Only the target next to it: the temp folder "<seq>.tmp.<pid>" was renamed onto it.
  CHECK(Entries(dir) == std::vector<std::string>{"seq"});
  for (const std::string& name : Entries(out)) CHECK(name.find(".tmp.") == std::string::npos);
  // The bytes do not depend on the target having existed before.
  const std::string fresh = dynref::test::ScratchDir("synth_replace_fresh") + "/seq";
  GenerateSequence(Options("walking_xyz", 2, fresh));
  std::map<std::string, std::string> ta, tb;
  ReadTree(out, "", &ta);
  ReadTree(fresh, "", &tb);
  CHECK(ta == tb);
}

TEST_CASE("synth refuses to overwrite a folder it did not write, exit 2", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("synth_refuse");
  const std::string other = dir + "/photos";
  REQUIRE(dynref::test::RunShell("mkdir -p " + dynref::test::Quote(other) + " && echo keep > " +
                                 dynref::test::Quote(other + "/notes.txt")).exit_code == 0);
  dynref::test::ExpectBadInput("synth --preset walking_xyz --frames 1 --out " + dynref::test::Quote(other),
                               "was not written by dynref synth");
  CHECK(dynref::test::ReadFileBytes(other + "/notes.txt") == "keep\n");
  CHECK(Entries(other).size() == 1);
  CHECK(Entries(dir).size() == 1);  // no temp folder left next to it
  // A plain file in the way is refused too.
  dynref::test::WriteText(dir + "/file", "x");
  dynref::test::ExpectBadInput("synth --preset walking_xyz --frames 1 --out " + dynref::test::Quote(dir + "/file"),
                               "not a directory");
  CHECK(dynref::test::ReadFileBytes(dir + "/file") == "x");
  CHECK_THROWS_AS(GenerateSequence(Options("walking_xyz", 1, other)), dynref::InputError);
}

TEST_CASE("synth --width: a small sequence with scaled intrinsics, masks and detections of its size") {
  // Issue 37: the config-mutation fuzzer runs ~2,000 mutants on one small shared sequence.
  const std::string dir = dynref::test::ScratchDir("synth_width");
  SynthOptions o = Options("walking_xyz", 2, dir);
  o.width = 160, o.detections = "ideal";
  GenerateSequence(o);
  const dynref::Sequence seq = dynref::OpenSequence(dir);
  REQUIRE(seq.frames.size() == 2);
  CHECK(seq.camera.width == 160);
  CHECK(seq.camera.height == 120);
  CHECK(seq.camera.fx == Approx(535.4 / 4));
  CHECK(seq.camera.fy == Approx(539.2 / 4));
  CHECK(seq.camera.cx == Approx((320.1 + 0.5) / 4 - 0.5));
  CHECK(seq.camera.cy == Approx((247.6 + 0.5) / 4 - 0.5));
  CHECK(seq.camera.baseline_m() == Approx(40.0 / 535.4));  // bf scales with fx
  for (const auto& f : seq.frames) {
    CHECK(dynref::LoadRgb(seq, f).size() == cv::Size(160, 120));
    CHECK(dynref::LoadDepthMeters(seq, f).size() == cv::Size(160, 120));
  }
  const dynref::DetectionsReader ideal(dir + "/detections/ideal");
  const dynref::FrameDetections d = ideal.Read(seq.frames[0].rgb_stamp_text);
  REQUIRE(!d.instances.empty());
  for (const auto& inst : d.instances) {
    CHECK(inst.x_max <= 159);
    CHECK(inst.y_max <= 119);
  }
  const std::string meta = dynref::test::ReadFileBytes(dir + "/synth.yaml");
  CHECK(meta.find(" --width 160)") != std::string::npos);
  CHECK(meta.find("\nwidth: 160\nheight: 120\n") != std::string::npos);
  // The default writes no width line (full-size synth.yaml unchanged).
  const std::string full = dynref::test::ScratchDir("synth_width_full");
  GenerateSequence(Options("walking_xyz", 1, full));
  CHECK(dynref::test::ReadFileBytes(full + "/synth.yaml").find("width") == std::string::npos);
  for (int bad : {-4, 32, 60, 161, 644}) {
    INFO(bad);
    SynthOptions b = Options("walking_xyz", 1, dir + "_bad");
    b.width = bad;
    CHECK_THROWS_WITH(GenerateSequence(b), Catch::Contains("--width"));
  }
}

TEST_CASE("synth rejects negative or overflowing seeds and absurd frame counts, exit 2", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("synth_ranges");
  const std::string base = "synth --preset walking_xyz --frames 1 --out " + dynref::test::Quote(dir + "/s");
  for (const char* seed : {"-1", "99999999999999999999999", "18446744073709551616", "12x", "''", "+3"}) {
    INFO(seed);
    dynref::test::ExpectBadInput(base + " --seed " + seed, "--seed");
    CHECK(!dynref::test::FileExists(dir + "/s"));
  }
  dynref::test::ExpectBadInput("synth --preset walking_xyz --frames 2000000000 --out " + dynref::test::Quote(dir + "/f"),
                               "--frames: must be <= 100000");
  CHECK(!dynref::test::FileExists(dir + "/f"));
  dynref::test::ExpectBadInput("synth --preset walking_xyz --frames 1 --width 63 --out " + dynref::test::Quote(dir + "/w"),
                               "--width: must be 0 (640) or a multiple of 4 in 64..640 (got 63)");
  CHECK(!dynref::test::FileExists(dir + "/w"));
  CHECK_THROWS_AS(GenerateSequence(Options("walking_xyz", dynref::synth::kMaxFrames + 1, dir + "/g")),
                  dynref::InputError);
  // The largest seed is accepted and written as given.
  const auto r = dynref::test::RunDynref(base + " --seed 18446744073709551615");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(dynref::test::ReadFileBytes(dir + "/s/synth.yaml").find("\nseed: 18446744073709551615\n") != std::string::npos);
}

TEST_CASE("synth-montage errors name its real options --frames-per-row and --tile-width", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("synth_montage_opts");
  GenerateSequence(Options("walking_xyz", 1, dir + "/wx"));
  const std::string base = "synth-montage " + dynref::test::Quote(dir + "/wx") + " --out " + dynref::test::Quote(dir + "/m.png");
  for (const std::string bad : {"--frames-per-row 0", "--frames-per-row 9", "--tile-width 10", "--tile-width 641"}) {
    INFO(bad);
    const auto r = dynref::test::RunDynref(base + " " + bad);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(bad.substr(0, bad.find(' ')) + ": must be in") != std::string::npos);
    CHECK(r.output.find("--montage-") == std::string::npos);
    CHECK(!dynref::test::FileExists(dir + "/m.png"));
  }
}
