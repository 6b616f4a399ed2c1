// TemporalLinker (issue 39): identity across frames, carrying a missed person max_gap frames
// along the corner line, then ending the track.
#include <array>
#include <catch2/catch.hpp>

#include "detect/temporal_links.h"

using namespace dynref;

namespace {

FrameDetections Frame(std::vector<std::array<double, 4>> boxes) {
  FrameDetections f;
  int id = 0;
  for (const auto& b : boxes) {
    DetectedInstance d;
    d.id = ++id;
    d.class_id = 0;
    d.class_name = "person";
    d.confidence = 0.4;
    d.x_min = b[0];
    d.y_min = b[1];
    d.x_max = b[2];
    d.y_max = b[3];
    f.instances.push_back(d);
  }
  return f;
}

}  // namespace

TEST_CASE("detect: a person missed for two frames keeps its track and moves along its corner line") {
  detect::TemporalOptions o;
  o.max_gap = 2;
  detect::TemporalLinker linker(o, cv::Size(640, 480));
  std::vector<detect::TrackLink> links;
  linker.Process(Frame({{100, 100, 200, 300}, {400, 100, 500, 300}}), 0.0, &links);
  REQUIRE(links.size() == 2);
  CHECK(links[0].track == 1);
  CHECK(links[1].track == 2);
  linker.Process(Frame({{410, 100, 510, 300}, {110, 100, 210, 300}}), 1.0, &links);  // order swapped
  CHECK(links[0].track == 2);
  CHECK(links[1].track == 1);
  // Frame 2: person 1 missed -> carried at x = 120 (line through 100, 110), box only.
  FrameDetections f2 = linker.Process(Frame({{420, 100, 520, 300}}), 2.0, &links);
  REQUIRE(f2.instances.size() == 2);
  CHECK(f2.instances[1].id == 2);
  CHECK_FALSE(f2.instances[1].has_mask);
  CHECK(f2.instances[1].x_min == Approx(120.0));
  CHECK(f2.instances[1].confidence == 0.4);
  REQUIRE(links.size() == 2);
  CHECK(links[1].track == 1);
  CHECK(links[1].carried);
  linker.Process(Frame({{430, 100, 530, 300}}), 3.0, &links);  // second miss: still carried
  CHECK(links.size() == 2);
  linker.Process(Frame({{440, 100, 540, 300}}), 4.0, &links);  // third miss: ended
  CHECK(links.size() == 1);
  CHECK(linker.carried_total() == 2);
  // Found again after the end: a new identity.
  linker.Process(Frame({{440, 100, 540, 300}, {150, 100, 250, 300}}), 5.0, &links);
  CHECK(links[1].track == 3);
}

TEST_CASE("detect: temporal options are checked and the corner fit is the least-squares line") {
  detect::TemporalOptions o;
  o.max_gap = -1;
  CHECK_THROWS_AS(o.Check(), std::invalid_argument);
  o.max_gap = 2;
  o.iou_link = 0;
  CHECK_THROWS_AS(o.Check(), std::invalid_argument);
  const cv::Point2d p = detect::PredictCornerLsq({{0, 10, 1.0}, {2, 10, 2.0}, {4, 10, 3.0}}, 4.0);
  CHECK(p.x == Approx(6.0));
  CHECK(p.y == Approx(10.0));
  CHECK(detect::PredictCornerLsq({{5, 7, 1.0}}, 9.0) == cv::Point2d(5, 7));
}
