// Sequence reader: the real TUM fr1_desk frames, camera selection, and every bad folder.
#include <catch2/catch.hpp>

#include <fstream>

#include "core/error.h"
#include "io/sequence.h"
#include "test_support.h"
#include "io/image_file.h"

using namespace dynref;

TEST_CASE("sequence: real TUM fr1_desk 9 frames") {
  const std::string root = test::SourcePath("datasets/real/tum_fr1_desk_9frames");
  const Sequence seq = OpenSequence(root);
  CHECK(seq.camera.name == "tum_fr1");
  CHECK(seq.camera.fx == 517.3);
  CHECK(seq.camera.depth_factor == 5000.0);
  CHECK(seq.rgb_count == 9);
  CHECK(seq.depth_count == 9);
  REQUIRE(seq.frames.size() == 9);
  CHECK(seq.groundtruth.size() == 2335);
  // Same pairs as the repository's associate.py output for the first two frames.
  CHECK(seq.frames[0].rgb_stamp_text == "1305031453.359684");
  CHECK(seq.frames[0].depth_path == root + "/depth/1305031453.374112.png");
  CHECK(seq.frames[1].rgb_stamp_text == "1305031453.391690");
  CHECK(seq.frames[1].depth_path == root + "/depth/1305031453.404816.png");
  for (size_t i = 0; i < seq.frames.size(); ++i) {
    const FrameEntry& f = seq.frames[i];
    CHECK(f.index == static_cast<int>(i));
    CHECK(std::abs(f.rgb_stamp - f.depth_stamp) < 0.02);
    if (i > 0) CHECK(f.rgb_stamp > seq.frames[i - 1].rgb_stamp);
  }
  const cv::Mat raw = dynref::ImageRead(seq.frames[0].depth_path, cv::IMREAD_UNCHANGED);
  CHECK(raw.type() == CV_16UC1);
  const cv::Mat rgb = LoadRgb(seq, seq.frames[4]);
  CHECK(rgb.type() == CV_8UC3);
  CHECK(rgb.cols == 640);
  CHECK(rgb.rows == 480);
  for (const FrameEntry& f : seq.frames) {
    const cv::Mat depth = LoadDepthMeters(seq, f);
    REQUIRE(depth.type() == CV_32FC1);
    REQUIRE(depth.size() == cv::Size(640, 480));
    double min_m = 1e9, max_m = 0;
    int valid = 0;
    for (int v = 0; v < depth.rows; ++v)
      for (int u = 0; u < depth.cols; ++u) {
        const float z = depth.at<float>(v, u);
        if (z <= 0) continue;
        ++valid;
        min_m = std::min(min_m, double(z));
        max_m = std::max(max_m, double(z));
      }
    // Kinect on a desk: most pixels valid, depth between ~0.4 m and a few metres.
    CHECK(size_t(valid) > depth.total() / 2);
    CHECK(min_m > 0.3);
    CHECK(max_m < 10.0);
  }
  // 16-bit value / 5000 = metres, exactly.
  const cv::Mat depth0 = LoadDepthMeters(seq, seq.frames[0]);
  CHECK(depth0.at<float>(240, 320) == float(raw.at<uint16_t>(240, 320) / 5000.0));
}

TEST_CASE("sequence: an associate.py output file replaces rgb.txt/depth.txt association") {
  const std::string root = test::SourcePath("datasets/real/tum_fr1_desk_9frames");
  SequenceOptions opt;
  opt.association_file = "source_meta/associate_from_repo.txt";  // relative to the folder
  opt.camera = "tum_fr1";
  const Sequence seq = OpenSequence(root, opt);
  REQUIRE(seq.frames.size() == 2);
  CHECK(seq.frames[1].rgb_stamp_text == "1305031453.391690");
  CHECK(seq.frames[1].depth_stamp == 1305031453.404816);
  CHECK(seq.frames[1].depth_path == root + "/depth/1305031453.404816.png");
  CHECK(seq.frames[1].rgb_line == 2);
  CHECK(seq.association_source.find("associate_from_repo.txt") != std::string::npos);
}

TEST_CASE("sequence: camera selection") {
  const std::string root = test::SourcePath("datasets/real/tum_fr1_desk_9frames");
  std::string source;
  CHECK(ResolveSequenceCamera(root, "", &source).name == "tum_fr1");
  CHECK(source.find("folder name") != std::string::npos);
  CHECK(ResolveSequenceCamera(root, "tum_fr3", &source).fx == 535.4);
  CHECK(ResolveSequenceCamera("/x/rgbd_dataset_freiburg2_desk", "", nullptr).name == "tum_fr2");
  CHECK(ResolveSequenceCamera("/x/rgbd_dataset_freiburg3_walking_xyz", "", nullptr).name ==
        "tum_fr3");
  CHECK(ResolveSequenceCamera("/x/rgbd_bonn_crowd", "", nullptr).name == "bonn");
  CHECK_THROWS_AS(ResolveSequenceCamera("/x/my_recording", "", nullptr), InputError);
  CHECK_THROWS_AS(ResolveSequenceCamera("/x/frame100", "", nullptr), InputError);
  CHECK_THROWS_AS(ResolveSequenceCamera(root, "no_such_camera", nullptr), InputError);
  // A --camera that names a file (.yaml/.yml or a path) is reported as a missing file, not as an
  // unknown preset.
  using Catch::Matchers::Contains;
  for (const std::string missing : {"nope.yaml", "nope.yml", "cams/nope"}) {
    INFO(missing);
    CHECK_THROWS_WITH(ResolveSequenceCamera(root, missing, nullptr),
                      Contains(missing + ": camera YAML not found"));
  }
  const std::string dir = test::ScratchDir("io_seq_camera");
  Camera c = CameraPreset("synthetic");
  c.width = 8;
  c.height = 6;
  c.cx = 4.0;  // the principal point lies inside the image
  c.cy = 3.0;
  WriteOrbSlamCameraYaml(c, dir + "/camera.yaml");
  CHECK(ResolveSequenceCamera(dir, "", &source).width == 8);
  CHECK(source == "camera.yaml in the folder");
}
