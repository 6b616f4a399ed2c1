// Hand boxes (datasets/real/..._person_boxes.txt), matching at IoU 0.5, score summaries (issue 39).
#include <catch2/catch.hpp>
#include <fstream>

#include "core/error.h"
#include "detect/box_eval.h"
#include "test_support.h"

using namespace dynref;
using dynref::test::ScratchDir;
using dynref::test::SourcePath;

namespace {

DetectedInstance Person(int id, double conf, double x0, double y0, double x1, double y1) {
  DetectedInstance d;
  d.id = id;
  d.class_id = 0;
  d.class_name = "person";
  d.confidence = conf;
  d.x_min = x0;
  d.y_min = y0;
  d.x_max = x1;
  d.y_max = y1;
  return d;
}

}  // namespace

TEST_CASE("detect: the committed hand boxes hold two persons in each of the 10 real frames") {
  const auto boxes =
      detect::ReadHandBoxes(SourcePath("datasets/real/tum_fr3_walking_halfsphere_10rgb_person_boxes.txt"));
  REQUIRE(boxes.size() == 20);
  std::map<std::string, int> per_frame;
  for (const auto& b : boxes) {
    ++per_frame[b.stamp_text];
    CHECK(b.class_name == "person");
    CHECK(b.x_min >= 0);
    CHECK(b.x_max <= 639);
    CHECK(b.y_max <= 479);
    CHECK((b.x_max - b.x_min) * (b.y_max - b.y_min) > 150 * 150);  // both people are large
  }
  CHECK(per_frame.size() == 10);
  for (const auto& [stamp, n] : per_frame) CHECK(n == 2);
}

TEST_CASE("detect: matching against hand boxes counts one-to-one matches at IoU 0.5") {
  const std::vector<detect::HandBox> truth = {{"1.0", "person", "a", 0, 0, 99, 99}, {"1.0", "person", "b", 200, 0, 299, 99},
                                              {"2.0", "person", "a", 0, 0, 99, 99}};
  std::map<std::string, FrameDetections> frames;
  frames["1.0"].instances = {Person(1, 0.9, 0, 0, 99, 99), Person(2, 0.8, 2, 2, 97, 97),  // duplicate of a
                             Person(3, 0.2, 200, 0, 299, 99)};                             // b, low score
  frames["2.0"].instances = {Person(1, 0.6, 60, 0, 159, 99)};                              // IoU 0.25 with a
  detect::MatchCounts all = detect::MatchAgainstHandBoxes(frames, truth, "person", 0.0, 0.5);
  CHECK(all.truth == 3);
  CHECK(all.detections == 4);
  CHECK(all.matched == 2);  // a (once) and b in frame 1
  const detect::MatchCounts high = detect::MatchAgainstHandBoxes(frames, truth, "person", 0.5, 0.5);
  CHECK(high.detections == 3);
  CHECK(high.matched == 1);
  CHECK(high.Recall() == Approx(1.0 / 3));
  CHECK(high.Precision() == Approx(1.0 / 3));
  CHECK(detect::InclusiveBoxIou(0, 0, 99, 99, 0, 0, 99, 99) == 1.0);
  CHECK(detect::InclusiveBoxIou(0, 0, 99, 99, 50, 0, 149, 99) == Approx(50.0 / 150.0));
}

TEST_CASE("detect: score summary per class and counts at cuts") {
  std::map<std::string, FrameDetections> frames;
  frames["1"].instances = {Person(1, 0.31, 0, 0, 1, 1), Person(2, 0.56, 0, 0, 1, 1)};
  frames["2"].instances = {Person(1, 0.42, 0, 0, 1, 1)};
  const auto s = detect::SummariseScores(frames, {0.3, 0.5});
  REQUIRE(s.count("person"));
  const detect::ScoreSummary& p = s.at("person");
  CHECK(p.count == 3);
  CHECK(p.min == 0.31);
  CHECK(p.median == 0.42);
  CHECK(p.max == 0.56);
  CHECK(p.at_least == std::vector<int>{3, 1});
}

TEST_CASE("detect: a malformed hand-box line is an InputError naming the line") {
  const std::string path = ScratchDir("hand_boxes_bad") + "/boxes.txt";
  std::ofstream(path) << "# header\n1.0 person a 0 0 10\n";
  CHECK_THROWS_WITH(detect::ReadHandBoxes(path), Catch::Contains("boxes.txt:2"));
  std::ofstream(path) << "1.0 person a 10 0 5 10\n";
  CHECK_THROWS_WITH(detect::ReadHandBoxes(path), Catch::Contains("max < min"));
}
