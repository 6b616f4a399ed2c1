// Issue 37 reliability items of the dynref front end: a failed write to standard output is an
// error (exit 2, one message) for every command; image codecs' own lines do not precede dynref's
// message; `enhance` on an image too small for its two-scale step; an installed, moved prefix
// finds its configs and models.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_support.h"
#include "io/image_file.h"

using dynref::test::FileExists;
using dynref::test::Quote;
using dynref::test::RunDynref;
using dynref::test::RunShell;
using dynref::test::ScratchDir;
using dynref::test::SourcePath;
using dynref::test::WriteText;
namespace fs = std::filesystem;

namespace {

const std::string kFullMessage = "dynref: error: cannot write standard output (No space left on device)";

const std::string kTraj =
    "1.0 0 0 0 0 0 0 1\n1.03125 0.1 0 0 0 0 0 1\n1.0625 0.2 0 0 0 0 0 1\n"
    "1.09375 0.3 0.01 0 0 0 0 1\n1.125 0.4 0 0.02 0 0 0 1\n";

// Runs dynref with stdout on /dev/full (stderr captured): exit 2 and the one message.
void ExpectFullDisk(const std::string& args) {
  const auto r = RunShell("( " + Quote(dynref::test::DynrefExe()) + " " + args + " >/dev/full )");
  INFO("dynref " << args << "\n" << r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(kFullMessage) != std::string::npos);
}

// The same command with stdout on /dev/null succeeds (the failure above is the write, not the input).
void ExpectOkToNull(const std::string& args) {
  const auto r = RunShell("( " + Quote(dynref::test::DynrefExe()) + " " + args + " >/dev/null )");
  INFO("dynref " << args << "\n" << r.output);
  CHECK(r.exit_code == 0);
}

}  // namespace

TEST_CASE("cli: standard output on a full disk exits 2 with one message (issue 37)", "[cli]") {
  REQUIRE(FileExists("/dev/full"));
  const std::string d = ScratchDir("cli_stdout_full");
  const std::string gt = WriteText(d + "/gt.txt", kTraj);
  const std::string eval = "eval --gt " + Quote(gt) + " --est " + Quote(gt) + " --delta 1 --delta-unit f";
  const std::string info = "info " + Quote(SourcePath("datasets/real/tum_fr1_desk_9frames"));
  for (const std::string& args : {eval, info, std::string("reproduce --list"), std::string("version"), std::string("--help")}) {
    ExpectOkToNull(args);
    ExpectFullDisk(args);
  }
}

TEST_CASE("cli: trace dump, trace feature, diff and map-eval on a full disk exit 2 with one message (issue 37) end to end", "[cli]") {
  const std::string d = ScratchDir("cli_stdout_full_run");
  REQUIRE(RunDynref("synth --preset walking_xyz --frames 4 --seed 1 --out " + Quote(d + "/seq")).exit_code == 0);
  REQUIRE(RunDynref("run --method orb --no-progress --trace full --sequence " + Quote(d + "/seq") + " --out " +
                    Quote(d + "/run")).exit_code == 0);
  const std::string run = Quote(d + "/run");
  const std::vector<std::string> commands = {
      "trace dump " + run, "trace feature " + run + " f0.0", "diff " + run + " " + run,
      "map-eval " + Quote(d + "/seq/gt/static_observed.ply") + " --gt " + Quote(d + "/seq") + " --trajectory " +
          Quote(d + "/seq/groundtruth.txt")};
  for (const std::string& args : commands) {
    ExpectOkToNull(args);
    ExpectFullDisk(args);
  }
  // trace dump used to exit 2 without a word.
  const auto dump = RunShell("( " + Quote(dynref::test::DynrefExe()) + " trace dump " + run + " >/dev/full )");
  CHECK(dump.output.rfind("dynref: error: cannot write standard output", 0) == 0);
}

TEST_CASE("cli: libpng / libjpeg / OpenCV lines do not precede dynref's message on a broken image (issue 37)", "[cli]") {
  const std::string d = ScratchDir("cli_codec_messages");
  cv::Mat img(72, 96, CV_8UC3, cv::Scalar(10, 200, 30));
  std::vector<uchar> png;
  REQUIRE(dynref::ImageEncode(".png", img, png));
  std::string bytes(png.begin(), png.end());
  bytes[20] = char(bytes[20] ^ 0xff);  // IHDR CRC error
  std::ofstream(d + "/crc.png", std::ios::binary) << bytes;
  std::ofstream(d + "/trunc.png", std::ios::binary) << std::string(png.begin(), png.begin() + 60);
  std::ofstream(d + "/trunc.jpg", std::ios::binary) << std::string("\xff\xd8\xff\xe0garbage", 11);
  struct Case {
    std::string file, note;
  };
  for (const Case& c : {Case{"crc.png", "libpng error: IHDR: CRC error"}, Case{"trunc.png", "libpng error: Read Error"},
                        Case{"trunc.jpg", "libjpeg: Premature end of JPEG file"}, Case{"missing.png", ""}}) {
    for (const std::string& cmd : {"detect --source hog --image " + Quote(d + "/" + c.file) + " --out " + Quote(d + "/det"),
                                   "enhance " + Quote(d + "/" + c.file) + " --out " + Quote(d + "/enh")}) {
      const auto r = RunDynref(cmd);
      INFO(cmd << "\n" << r.output);
      CHECK(r.exit_code == 2);
      // dynref's own message comes first; the codec's reason, if any, follows as a note.
      CHECK(r.output.rfind("dynref: error: " + d + "/" + c.file, 0) == 0);
      CHECK(r.output.find("[ WARN") == std::string::npos);
      if (!c.note.empty()) CHECK(r.output.find("\ndynref: note: " + c.note) != std::string::npos);
      if (c.file == "missing.png") CHECK(r.output.find("note:") == std::string::npos);
    }
  }
}

TEST_CASE("cli: enhance on an image too small for the two-scale step is a clear error (issue 37)", "[cli]") {
  const std::string d = ScratchDir("cli_enhance_tiny");
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(2, 1), cv::Size(1, 5)}) {
    const std::string name = std::to_string(size.width) + "x" + std::to_string(size.height);
    REQUIRE(dynref::ImageWrite(d + "/" + name + ".png", cv::Mat(size, CV_8UC3, cv::Scalar(40, 80, 120))));
    const auto r = RunDynref("enhance " + Quote(d + "/" + name + ".png") + " --out " + Quote(d + "/out" + name));
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(name + ".png: image is " + name + ": the enhancement's two-scale step (epi.enhance down = 0.5) "
                                                          "needs both sides >= 2 px") != std::string::npos);
    CHECK(r.output.find("Assertion") == std::string::npos);
    CHECK_FALSE(FileExists(d + "/out" + name));
  }
  REQUIRE(dynref::ImageWrite(d + "/2x2.png", cv::Mat(2, 2, CV_8UC3, cv::Scalar(40, 80, 120))));
  CHECK(RunDynref("enhance " + Quote(d + "/2x2.png") + " --out " + Quote(d + "/out2x2")).exit_code == 0);
}

TEST_CASE("cli: cmake --install into a prefix, moved, runs --method sgdo from there (issue 37) end to end", "[cli]") {
  const std::string d = ScratchDir("cli_install");
  const std::string prefix = d + "/prefix", moved = d + "/elsewhere/moved";
  const auto install = RunShell(Quote(DYNREF_CMAKE_COMMAND) + " --install " + Quote(DYNREF_BINARY_DIR) + " --prefix " +
                                Quote(prefix));
  INFO(install.output);
  REQUIRE(install.exit_code == 0);
  for (const char* f : {"bin/dynref", "share/dynref/configs/sgdo.yaml", "share/dynref/configs/orb.yaml",
                        "share/dynref/models/nanodet.onnx", "share/dynref/models/selfie.onnx",
                        "share/dynref/reports/paper-tables", "lib/dynref/dynref_oiio_png.so"})
    CHECK(FileExists(prefix + "/" + f));
  fs::create_directories(d + "/elsewhere");
  fs::rename(prefix, moved);
  const std::string exe = Quote(moved + "/bin/dynref");
  REQUIRE(RunShell(exe + " synth --preset walking_xyz --frames 4 --seed 1 --detections yolo-like --out " +
                   Quote(d + "/seq")).exit_code == 0);
  // The configs come from the moved prefix: a config the source tree does not have proves it.
  WriteText(moved + "/share/dynref/configs/only_installed.yaml",
            dynref::test::ReadFileBytes(moved + "/share/dynref/configs/sgdo.yaml"));
  // sgdo with --overlays: the OpenImageIO PNG module is loaded from the moved prefix's lib/dynref.
  for (const std::string method : {"sgdo", "only_installed"}) {
    const std::string overlays = method == "sgdo" ? " --overlays --trace full" : "";
    const auto r = RunShell(exe + " run --method " + method + overlays + " --no-progress --sequence " + Quote(d + "/seq") +
                            " --detections " + Quote(d + "/seq/detections/yolo-like") + " --out " +
                            Quote(d + "/run_" + method));
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(FileExists(d + "/run_" + method + "/trajectory.txt"));
  }
  CHECK(FileExists(d + "/run_sgdo/overlays/overlay_000003.png"));
  // The bundled models are found there too (nanodet + selfie, sha256-checked).
  const auto det = RunShell(exe + " detect --source nanodet --sequence " + Quote(d + "/seq") + " --frames 0-0 --out " +
                            Quote(d + "/det"));
  INFO(det.output);
  CHECK(det.exit_code == 0);
}

// Issue 37: every call cost ~0.5 CPU-s and 140 MB before main, loading ~280 shared libraries
// (OpenImageIO, OpenCV's imgcodecs/ximgproc and GDAL behind them). They are loadable modules now
// (core/modules.h): a command that touches no image loads none of them. The dynamic loader's own
// list (LD_DEBUG=libs) is the evidence; libopencv_core is the control that the list is read.
TEST_CASE("cli: dynref version and eval load neither OpenImageIO nor imgcodecs nor GDAL (issue 37)", "[cli]") {
  const std::string d = ScratchDir("cli_startup_libs");
  WriteText(d + "/t.txt", kTraj);
  for (const std::string& args : std::vector<std::string>{"version", "eval --delta-unit f --delta 1 --gt " + Quote(d + "/t.txt") + " --est " + Quote(d + "/t.txt")}) {
    // The loader's list goes to stderr; the command's own output is dropped.
    const auto r = RunShell("( LD_DEBUG=libs " + Quote(dynref::test::DynrefExe()) + " " + args + " 2>&1 >/dev/null )");
    INFO(args);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("libopencv_core") != std::string::npos);
    for (const char* lib : {"libOpenImageIO", "libopencv_imgcodecs", "libopencv_ximgproc", "libgdal"})
      CHECK(r.output.find(lib) == std::string::npos);
  }
}

// The image path loads the module once and reads the same pixels cv::imread does.
TEST_CASE("cli: the OpenCV module is loaded for an image and gives imread's pixels (issue 37)") {
  const std::string d = ScratchDir("cli_module_image");
  const cv::Mat img(3, 4, CV_16UC1, cv::Scalar(4321));
  REQUIRE(dynref::ImageWrite(d + "/d.png", img));
  const cv::Mat back = dynref::ImageRead(d + "/d.png", cv::IMREAD_UNCHANGED);
  REQUIRE(back.type() == CV_16UC1);
  CHECK(cv::countNonZero(back != img) == 0);
}
