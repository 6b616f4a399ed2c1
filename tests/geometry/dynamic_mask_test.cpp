#include <catch2/catch.hpp>

#include "geometry/dynamic_mask.h"

using namespace dynref;
using namespace dynref::geometry;

namespace {
FrameDetections TwoInstances() {
  FrameDetections d;
  d.stamp_text = "1.0";
  d.instance_ids = cv::Mat::zeros(40, 60, CV_16U);
  d.instance_ids(cv::Rect(10, 10, 5, 5)).setTo(1);  // person
  d.instance_ids(cv::Rect(40, 20, 4, 4)).setTo(2);  // chair (static class)
  d.instance_ids(cv::Rect(14, 14, 3, 3)).setTo(3);  // second person, overlapping after dilation
  d.instances = {{1, 0, "person", 0.9, 10, 10, 14, 14, true},
                 {2, 56, "chair", 0.8, 40, 20, 43, 23, true},
                 {3, 0, "person", 0.6, 14, 14, 16, 16, true}};
  return d;
}
}  // namespace

TEST_CASE("instance mask: person masks only, dilated, lowest id wins on overlap") {
  DynamicMaskOptions o;
  o.dilation_kernel_px = 3;
  const DynamicMask m = BuildDynamicMask(TwoInstances(), 60, 40, o);
  CHECK(m.instance_ids == std::vector<int>{1, 3});
  CHECK(cv::countNonZero(m.mask) > 25 + 9);
  CHECK(m.InMask(9, 9));     // dilation by 1 px
  CHECK(!m.InMask(8, 8));
  CHECK(!m.InMask(41, 21));  // chair is not prior-dynamic
  CHECK(m.InstanceAt(12, 12) == 1);
  CHECK(m.InstanceAt(14.2, 14.4) == 1);  // overlap -> lowest id
  CHECK(m.InstanceAt(17, 17) == 3);
  CHECK(m.InstanceAt(-1, 5) == 0);
  CHECK(m.InstanceAt(100, 5) == 0);
}

TEST_CASE("instance mask: confidence filter, no dilation, box-only instances") {
  DynamicMaskOptions o;
  o.dilation_kernel_px = 1;
  o.min_confidence = 0.7;
  const DynamicMask m = BuildDynamicMask(TwoInstances(), 60, 40, o);
  CHECK(m.instance_ids == std::vector<int>{1});
  CHECK(cv::countNonZero(m.mask) == 24);  // pixel (14,14) belongs to instance 3

  FrameDetections boxes;
  boxes.instances = {{5, 0, "person", 0.9, 2.5, 3, 6, 8, false}};
  const DynamicMask b = BuildDynamicMask(boxes, 60, 40, o);
  CHECK(b.InstanceAt(2, 3) == 5);
  CHECK(b.InstanceAt(6, 8) == 5);
  CHECK(b.InstanceAt(7, 8) == 0);
}

TEST_CASE("instance mask: static class labels and option checks") {
  const cv::Mat labels = StaticClassLabels(TwoInstances(), 60, 40, DynamicMaskOptions{});
  CHECK(labels.at<int16_t>(21, 41) == 56);
  CHECK(labels.at<int16_t>(12, 12) == -1);
  DynamicMaskOptions bad;
  bad.dilation_kernel_px = 4;
  CHECK_THROWS_WITH(bad.Check(), Catch::Contains("dilation_kernel_px"));
}
