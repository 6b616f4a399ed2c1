// `dynref info`: the real TUM frames, and every bad sequence folder through the CLI
// (message naming file and line, exit code 2).
#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <sys/stat.h>

#include "io/camera.h"
#include "test_support.h"
#include "io/image_file.h"

using dynref::test::ExpectBadInput;
using dynref::test::Quote;
using dynref::test::RunDynref;
using dynref::test::WriteText;

namespace {

// A tiny sequence folder: n frames of 8x6 images, camera.yaml with the same size.
void MakeSequence(const std::string& dir, int n, int depth_type, cv::Size depth_size) {
  ::mkdir((dir + "/rgb").c_str(), 0755);
  ::mkdir((dir + "/depth").c_str(), 0755);
  dynref::Camera cam = dynref::CameraPreset("synthetic");
  cam.width = 8;
  cam.height = 6;
  cam.cx = 4.0;  // the principal point lies inside the image
  cam.cy = 3.0;
  dynref::WriteOrbSlamCameraYaml(cam, dir + "/camera.yaml");
  std::string rgb_txt = "# color images\n", depth_txt = "# depth maps\n";
  for (int i = 0; i < n; ++i) {
    const std::string stamp = std::to_string(10 + i) + ".000000";
    dynref::ImageWrite(dir + "/rgb/" + stamp + ".png", cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 20, 30)));
    dynref::ImageWrite(dir + "/depth/" + stamp + ".png", cv::Mat(depth_size, depth_type, cv::Scalar(5000)));
    rgb_txt += stamp + " rgb/" + stamp + ".png\n";
    depth_txt += stamp + " depth/" + stamp + ".png\n";
  }
  WriteText(dir + "/rgb.txt", rgb_txt);
  WriteText(dir + "/depth.txt", depth_txt);
}

}  // namespace

TEST_CASE("info cli: real sequence and bad sequence folders exit 2 naming file and line", "[cli]") {
  const auto real = RunDynref("info " + Quote(dynref::test::SourcePath("datasets/real/tum_fr1_desk_9frames")));
  INFO(real.output);
  REQUIRE(real.exit_code == 0);
  CHECK(real.output.find("associated     9 RGB-D pairs") != std::string::npos);
  CHECK(real.output.find("2335 poses") != std::string::npos);
  CHECK(real.output.find("GT coverage    9 of 9") != std::string::npos);
  CHECK(real.output.find("fx 517.3  fy 516.5  cx 318.6  cy 255.3") != std::string::npos);

  const std::string base = dynref::test::ScratchDir("info_cli_bad");
  ExpectBadInput("info " + Quote(base + "/nope"), base + "/nope: sequence folder not found");

  auto fresh = [&](const std::string& name, int depth_type = CV_16UC1, cv::Size size = {8, 6}) {
    const std::string dir = base + "/" + name;
    ::mkdir(dir.c_str(), 0755);
    MakeSequence(dir, 3, depth_type, size);
    return dir;
  };
  const std::string good = fresh("good");
  CHECK(RunDynref("info " + Quote(good)).exit_code == 0);

  const std::string no_rgb = fresh("no_rgb_txt");
  ::remove((no_rgb + "/rgb.txt").c_str());
  ExpectBadInput("info " + Quote(no_rgb), no_rgb + "/rgb.txt: file not found");

  const std::string missing_img = fresh("missing_image");
  ::remove((missing_img + "/depth/11.000000.png").c_str());
  ExpectBadInput("info " + Quote(missing_img), missing_img + "/depth.txt:3: depth image listed but missing");

  const std::string eight = fresh("depth8", CV_8UC1);
  ExpectBadInput("info " + Quote(eight), eight + "/depth.txt:2: depth image");
  ExpectBadInput("info " + Quote(eight), "not a 1-channel 16-bit PNG (8-bit");

  const std::string mismatch = fresh("size_mismatch", CV_16UC1, {4, 3});
  ExpectBadInput("info " + Quote(mismatch), mismatch + "/depth.txt:2: image size mismatch");

  const std::string malformed = fresh("malformed");
  WriteText(malformed + "/rgb.txt", "10.000000 rgb/10.000000.png\n11.000000\n");
  ExpectBadInput("info " + Quote(malformed), malformed + "/rgb.txt:2: malformed line");

  const std::string nonnum = fresh("nonnum");
  WriteText(nonnum + "/depth.txt", "10.000000 depth/10.000000.png\nten depth/11.000000.png\n");
  ExpectBadInput("info " + Quote(nonnum), nonnum + "/depth.txt:2: timestamp 'ten' is not a number");

  const std::string order = fresh("order");
  WriteText(order + "/rgb.txt", "11.000000 rgb/11.000000.png\n10.000000 rgb/10.000000.png\n");
  ExpectBadInput("info " + Quote(order), order + "/rgb.txt:2: timestamps not increasing");

  const std::string zero = fresh("zero_pairs");
  WriteText(zero + "/depth.txt", "50.000000 depth/10.000000.png\n");
  ExpectBadInput("info " + Quote(zero), zero + "/rgb.txt: zero associated RGB/depth pairs");

  const std::string empty_gt = fresh("empty_gt");
  WriteText(empty_gt + "/groundtruth.txt", "# ground truth trajectory\n");
  ExpectBadInput("info " + Quote(empty_gt), empty_gt + "/groundtruth.txt: no poses");

  const std::string nan_gt = fresh("nan_gt");
  WriteText(nan_gt + "/groundtruth.txt", "10.0 0 0 0 0 0 0 1\n10.5 nan 0 0 0 0 0 1\n");
  ExpectBadInput("info " + Quote(nan_gt), nan_gt + "/groundtruth.txt:2: pose field tx is nan");

  // No camera.yaml and an uninformative folder name: asks for --camera.
  const std::string nocam = fresh("nocam");
  ::remove((nocam + "/camera.yaml").c_str());
  ExpectBadInput("info " + Quote(nocam), "pass --camera");
  const auto with_cam = RunDynref("info " + Quote(nocam) + " --camera synthetic");
  CHECK(with_cam.exit_code == 2);  // synthetic preset is 640x480, images are 8x6
  CHECK(with_cam.output.find(nocam + "/rgb.txt:2:") != std::string::npos);
}

TEST_CASE("info cli: a missing or out-of-range --camera YAML exits 2 naming file and line", "[cli]") {
  const std::string base = dynref::test::ScratchDir("info_cli_camera");
  const std::string seq = base + "/seq";
  ::mkdir(seq.c_str(), 0755);
  MakeSequence(seq, 3, CV_16UC1, {8, 6});
  ExpectBadInput("info " + Quote(seq) + " --camera " + Quote(base + "/nope.yaml"),
                 base + "/nope.yaml: camera YAML not found");
  const std::string bad = WriteText(
      base + "/bad.yaml",
      "%YAML:1.0\nCamera.fx: 535.4\nCamera.fy: 539.2\nCamera.cx: 5000\nCamera.cy: 3\n"
      "Camera.k1: 0\nCamera.k2: 0\nCamera.p1: 0\nCamera.p2: 0\nCamera.width: 8\n"
      "Camera.height: 6\nDepthMapFactor: 5000.0\n");
  ExpectBadInput("info " + Quote(seq) + " --camera " + Quote(bad),
                 bad + ":4: Camera.cx must lie inside the image");
}
