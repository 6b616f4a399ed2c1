// MGD-SLAM's box stage (seed 000 Sec. 3.3, spec E10): in-box features leave the relative
// (initial) pose with weight 0; on a lost frame, whose pose comes from relocalisation against the
// map, they keep their box prior 1 - P_init instead, and the trace carries that weight.
#include <catch2/catch.hpp>

#include "dynamic/mgd/stages.h"

using namespace dynref;

namespace {

// Two features, the first inside a person's box (class 0, confidence 0.9), the second outside.
Frame TwoFeatureFrame(const FrameDetections* det) {
  Frame f;
  f.index = 5;
  for (float u : {50.f, 200.f}) f.keys.emplace_back(u, 50.f, 7.f);
  f.keys_un = f.keys;
  f.map_point_ids.assign(2, -1);
  f.outlier.assign(2, 0);
  f.detections = det;
  return f;
}

// The weights the box stage leaves on the two features, with `lost` the tracking state.
std::vector<double> BoxWeights(bool lost, trace::TraceWriter& tr) {
  FrameDetections det;
  DetectedInstance person;
  person.id = 1, person.class_id = 0, person.confidence = 0.9;
  person.x_min = 0, person.y_min = 0, person.x_max = 100, person.y_max = 100;
  det.instances.push_back(person);
  Frame f = TwoFeatureFrame(&det);
  Map map;
  Camera cam = {};
  cam.width = 320, cam.height = 240, cam.fx = cam.fy = 250, cam.cx = 160, cam.cy = 120;
  auto state = std::make_shared<mgd::MgdState>();
  state->configured = true;
  mgd::BoxStage stage(state);
  FrameEdit edit(f, map, Hook::kBeforeInitialPose);
  StageContext ctx{edit, nullptr, nullptr, map, cam, tr, true, lost};
  stage.Run(ctx);
  return {f.Weight(0), f.Weight(1)};
}

}  // namespace

TEST_CASE("mgd boxes: in-box features leave the initial pose (weight 0), a lost frame keeps the box prior 0.5") {
  trace::TraceWriter off("", trace::Level::kOff, trace::RunHeader{});
  CHECK(BoxWeights(false, off) == std::vector<double>{0.0, 1.0});
  CHECK(BoxWeights(true, off) == std::vector<double>{0.5, 1.0});
}
