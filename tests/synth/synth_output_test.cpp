// dynref synth: TUM layout, determinism, every preset, CLI exit codes (issue 3).
#include <catch2/catch.hpp>

#include <dirent.h>
#include <opencv2/imgcodecs.hpp>
#include <sys/stat.h>

#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "synth/synth.h"
#include "synth/world.h"
#include "test_support.h"

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

TEST_CASE("synth: same arguments give byte-identical folders with blur and low light and all detections") {
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

TEST_CASE("synth: every preset generates and has people only where expected") {
  CHECK(dynref::synth::PresetNames().size() == 15);  // the presets table of datasets/README.md
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
    CHECK(has_person == (preset.rfind("static_", 0) != 0));
    if (preset == "moving_box") CHECK(ls.str().find("class_name: box, coco_id: -1") != std::string::npos);
  }
  CHECK_THROWS_AS(dynref::synth::GetPreset("walking_sideways"), dynref::InputError);
}

TEST_CASE("synth: CLI writes a sequence that dynref info reads and bad arguments exit 2") {
  const std::string dir = dynref::test::ScratchDir("synth_cli");
  const auto r = dynref::test::RunDynref("synth --preset walking_xyz --frames 3 --out '" + dir + "/wx'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto info = dynref::test::RunDynref("info '" + dir + "/wx'");
  INFO(info.output);
  CHECK(info.exit_code == 0);
  CHECK(info.output.find("3 RGB-D pairs") != std::string::npos);
  CHECK(info.output.find("GT coverage    3 of 3") != std::string::npos);
  CHECK(dynref::test::RunDynref("synth --preset nope --out '" + dir + "/x'").exit_code == 2);
  CHECK(dynref::test::RunDynref("synth --preset walking_xyz --detections magic --out '" + dir + "/y'").exit_code == 2);
  CHECK(dynref::test::RunDynref("synth --preset walking_xyz --frames -1 --out '" + dir + "/z'").exit_code == 2);
  const auto m = dynref::test::RunDynref("synth-montage '" + dir + "/wx' --frames-per-row 2 --out '" + dir + "/m.png'");
  INFO(m.output);
  CHECK(m.exit_code == 0);
  CHECK(!cv::imread(dir + "/m.png").empty());
}
