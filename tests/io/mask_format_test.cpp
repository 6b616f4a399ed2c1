// dynref-detections reading (issue 37): an instance-id PNG whose pixel values are not instances
// with a mask in the frame's .txt is an error naming the PNG, not a frame without masks.
#include <catch2/catch.hpp>

#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "io/mask_format.h"
#include "test_support.h"

using namespace dynref;

namespace {

FrameDetections OnePerson(int id_in_txt, uint16_t id_in_png) {
  FrameDetections f;
  f.stamp_text = "1.000000";
  DetectedInstance d;
  d.id = id_in_txt;
  d.class_id = 0;
  d.class_name = "person";
  d.confidence = 0.9;
  d.x_min = 2, d.y_min = 2, d.x_max = 5, d.y_max = 5;
  d.has_mask = true;
  f.instances.push_back(d);
  f.instance_ids = cv::Mat(8, 8, CV_16U, cv::Scalar(0));
  f.instance_ids(cv::Rect(2, 2, 4, 4)).setTo(id_in_png);
  return f;
}

std::string Write(const std::string& name, const FrameDetections& f) {
  const std::string dir = test::ScratchDir(name);
  DetectionsWriter w(dir, "test", "0");
  w.Write(f);
  w.Finish();
  return dir;
}

}  // namespace

TEST_CASE("mask format: instance ids of the PNG must be listed in the frame's .txt (issue 37)") {
  const DetectionsReader ok(Write("mask_format_ids_ok", OnePerson(1, 1)));
  CHECK(cv::countNonZero(ok.Read("1.000000", cv::Size(8, 8)).MaskOf(1)) == 16);
  const std::string dir = Write("mask_format_ids_bad", OnePerson(1, 7));
  const DetectionsReader bad(dir);
  CHECK_THROWS_WITH(bad.Read("1.000000", cv::Size(8, 8)),
                    Catch::Contains(dir + "/1.000000.png: pixel value 7 is not an instance with a mask in " + dir +
                                    "/1.000000.txt"));
}
