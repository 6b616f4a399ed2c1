// detect/detect_run.h: `dynref detect`'s option checks, image and sequence runs without the CLI.
#include <catch2/catch.hpp>
#include <sstream>

#include "core/error.h"
#include "detect/detect_run.h"
#include "io/image_file.h"
#include "test_support.h"

using namespace dynref;

TEST_CASE("detect run: argument combinations and option ranges are InputErrors naming the option") {
  detect::DetectRunOptions o;
  o.source = "hog";
  std::ostringstream out, timing;
  CHECK_THROWS_WITH(detect::RunDetection(o, out, timing), Catch::Contains("give exactly one of --sequence or --image"));
  o.sequence = test::SourcePath("datasets/real/tum_fr1_desk_9frames");
  CHECK_THROWS_WITH(detect::RunDetection(o, out, timing), Catch::Contains("--sequence needs --out DIR"));
  o.out = test::ScratchDir("detect_run_args") + "/out";
  o.options.nms_iou = 2;
  CHECK_THROWS_WITH(detect::RunDetection(o, out, timing), Catch::Contains("--nms-iou: must be in (0, 1], got 2"));
  o.options.nms_iou = 0.5;
  o.frames_given = true;
  CHECK_THROWS_WITH(detect::RunDetection(o, out, timing), Catch::Contains("--frames: empty value"));
  CHECK(out.str().empty());
}

TEST_CASE("detect run: an image and a sequence clip, results on `out`, timing only on `timing`") {
  const std::string dir = test::ScratchDir("detect_run_hog");
  detect::DetectRunOptions o;
  o.source = "hog";
  o.image = dir + "/small.png";
  REQUIRE(ImageWrite(o.image, cv::Mat(48, 64, CV_8UC3, cv::Scalar(90, 120, 150))));
  o.out = dir + "/image_out";
  std::ostringstream out, timing;
  detect::RunDetection(o, out, timing);
  CHECK(out.str() == o.image + " (64x48): 0 instances (0 masks)\n");
  CHECK(timing.str().empty());  // no --repeat
  CHECK(test::FileExists(o.out + "/format.txt"));

  o.image.clear();
  o.sequence = test::SourcePath("datasets/real/tum_fr1_desk_9frames");
  o.camera = "tum_fr1";
  o.frames = "0-0";
  o.out = dir + "/sequence_out";
  std::ostringstream seq_out, seq_timing;
  detect::RunDetection(o, seq_out, seq_timing);
  CHECK(seq_out.str().rfind("frame 0 ", 0) == 0);
  CHECK(seq_out.str().find("detect: 1 frames, source hog") != std::string::npos);
  CHECK(seq_timing.str().rfind("time: first frame ", 0) == 0);
  const std::string info = test::ReadFileBytes(o.out + "/detect_info.txt");
  CHECK(info.find("\nsource_spec hog\n") != std::string::npos);
  CHECK(info.find("\nframes 0-0\n") != std::string::npos);
  CHECK(info.find(" ms") == std::string::npos);  // no timings in the output folder
}
