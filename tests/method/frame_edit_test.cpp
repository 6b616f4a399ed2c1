// The narrow frame-edit handle (issue 12): what a stage may change, and when.
#include <catch2/catch.hpp>

#include "method/frame_edit.h"

using namespace dynref;

namespace {

Frame TwoFeatureFrame() {
  Frame f;
  f.index = 7;
  f.keys = f.keys_un = {cv::KeyPoint(10, 10, 7), cv::KeyPoint(20, 20, 7)};
  f.grey = cv::Mat(8, 8, CV_8U, cv::Scalar(3));
  f.map_point_ids = {4, -1};
  f.depth = {1.f, 1.f};
  f.u_right = {-1.f, -1.f};
  f.outlier = {0, 0};
  return f;
}

}  // namespace

TEST_CASE("frame edit: exclude and weight reach the frame, not before extraction") {
  Frame f = TwoFeatureFrame();
  Map map;
  FrameEdit before(f, map, Hook::kBeforeExtraction);
  CHECK_THROWS_AS(before.Exclude(0, "t", "r"), std::logic_error);
  CHECK_THROWS_AS(before.SetWeight(0, 0.5), std::logic_error);
  FrameEdit edit(f, map, Hook::kAfterExtraction);
  edit.Exclude(0, "t", "r");
  edit.SetWeight(1, 0.25);
  CHECK(f.IsExcluded(0));
  CHECK(f.map_point_ids[0] == -1);  // an excluded feature loses its map point
  CHECK_FALSE(f.IsExcluded(1));
  CHECK(f.Weight(1) == 0.25);
  CHECK(&edit.view() == &f);
}

TEST_CASE("frame edit: the grey image is replaceable before extraction only") {
  Frame f = TwoFeatureFrame();
  Map map;
  FrameEdit edit(f, map, Hook::kBeforeExtraction);
  edit.grey_for_extraction().setTo(200);
  CHECK(f.grey.at<uint8_t>(0, 0) == 200);
  edit.set_hook(Hook::kAfterExtraction);
  CHECK_THROWS_AS(edit.grey_for_extraction(), std::logic_error);
}

TEST_CASE("frame edit: landmark dynamic probability is stored on the map point") {
  Frame f = TwoFeatureFrame();
  Map map;
  const int64_t id = map.NewMapPoint(Eigen::Vector3d(0, 0, 2), 0, 0)->id;
  CHECK(map.mp(id)->dynamic.p_dynamic < 0);  // never set
  FrameEdit edit(f, map, Hook::kAfterInitialPose);
  edit.SetPointDynamicProbability(id, 0.75, "t.stage");
  CHECK(map.mp(id)->dynamic.p_dynamic == 0.75);
  CHECK(map.mp(id)->dynamic.frame == 7);
  CHECK(map.mp(id)->dynamic.stage == "t.stage");
  CHECK_THROWS_AS(edit.SetPointDynamicProbability(id, 1.5, "t"), std::logic_error);
  CHECK_THROWS_AS(edit.SetPointDynamicProbability(99, 0.5, "t"), std::logic_error);
}
