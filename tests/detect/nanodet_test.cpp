// The bundled NanoDet + selfie models on real photos (Debian darknet package, copied to
// tests/data/darknet/): persons where a person measured them by hand, masks on them, no person
// among horses, identical output on repeated runs.
#include <catch2/catch.hpp>

#include "detect/candidates.h"
#include "detect/detection_source.h"
#include "test_support.h"
#include "io/image_file.h"

using dynref::DetectedInstance;
using dynref::FrameDetections;
using dynref::test::SourcePath;

namespace {

struct HandBox {
  double x_min, y_min, x_max, y_max;
};

// Person boxes read by hand from zoomed crops with a 10-px grid (head top to feet, arm to arm).
const HandBox kPersonJpg = {191, 99, 274, 372};
const HandBox kKiteBlueJacket = {114, 613, 165, 761};
const HandBox kKiteDarkHoodie = {217, 699, 270, 856};

dynref::DetectionSource& Nanodet() {
  static auto source = dynref::MakeDetectionSource("nanodet", {});
  return *source;
}

cv::Mat Photo(const std::string& name) {
  cv::Mat im = dynref::ImageRead(SourcePath("tests/data/darknet/" + name), cv::IMREAD_COLOR);
  REQUIRE(!im.empty());
  return im;
}

double Iou(const DetectedInstance& d, const HandBox& h) {
  dynref::detect::Candidate a, b;
  a.x_min = d.x_min, a.y_min = d.y_min, a.x_max = d.x_max, a.y_max = d.y_max;
  b.x_min = h.x_min, b.y_min = h.y_min, b.x_max = h.x_max, b.y_max = h.y_max;
  return dynref::detect::BoxIou(a, b);
}

// The person instance best matching a hand box.
const DetectedInstance* BestPerson(const FrameDetections& f, const HandBox& h) {
  const DetectedInstance* best = nullptr;
  for (const auto& d : f.instances)
    if (d.class_name == "person" && (!best || Iou(d, h) > Iou(*best, h))) best = &d;
  return best;
}

void CheckPersonWithMask(const FrameDetections& f, const HandBox& h, cv::Point on_person) {
  const DetectedInstance* p = BestPerson(f, h);
  REQUIRE(p != nullptr);
  INFO("box [" << p->x_min << ", " << p->y_min << ", " << p->x_max << ", " << p->y_max << "] conf " << p->confidence);
  CHECK(Iou(*p, h) > 0.8);
  CHECK(p->class_id == 0);
  CHECK(p->confidence > 0.5);
  REQUIRE(p->has_mask);
  const cv::Mat mask = f.MaskOf(p->id);
  const cv::Rect hand(int(h.x_min), int(h.y_min), int(h.x_max - h.x_min), int(h.y_max - h.y_min));
  const double area = cv::countNonZero(mask), inside = cv::countNonZero(mask(hand));
  INFO("mask " << area << " px, " << inside << " inside the hand box of " << hand.area() << " px");
  CHECK(inside / area > 0.95);          // the mask stays on the person
  CHECK(inside / hand.area() > 0.45);   // and covers the body, not a sliver
  CHECK(mask.at<uchar>(on_person) == 255);
}

}  // namespace

TEST_CASE("nanodet: one person on person.jpg, with a mask on the person, dog and horse box-only") {
  const cv::Mat im = Photo("person.jpg");
  const FrameDetections f = Nanodet().Detect(im, "person");
  int persons = 0;
  for (const auto& d : f.instances) persons += d.class_name == "person";
  CHECK(persons == 1);
  CheckPersonWithMask(f, kPersonJpg, {230, 190});  // blue jacket
  bool horse = false, dog = false;
  for (const auto& d : f.instances) {
    horse = horse || (d.class_name == "horse" && d.x_min > 380 && d.x_max > 580);
    dog = dog || (d.class_name == "dog" && d.x_max < 220 && d.y_min > 240);
    if (d.class_name != "person") CHECK_FALSE(d.has_mask);
  }
  CHECK(horse);
  CHECK(dog);
  CHECK(f.instance_ids.type() == CV_16U);
  CHECK(f.instance_ids.at<uint16_t>(200, 330) == 0);  // grass
}

TEST_CASE("nanodet: kite.jpg, the two people in front found and masked, more people behind") {
  const cv::Mat im = Photo("kite.jpg");
  const FrameDetections f = Nanodet().Detect(im, "kite");
  CheckPersonWithMask(f, kKiteBlueJacket, {140, 660});
  CheckPersonWithMask(f, kKiteDarkHoodie, {243, 740});
  int persons = 0, kites = 0;
  for (const auto& d : f.instances) {
    persons += d.class_name == "person";
    kites += d.class_name == "kite";
  }
  CHECK(persons >= 4);  // the small people on the beach and in the water
  CHECK(kites >= 2);
  // Ids 1..n in descending confidence.
  for (size_t i = 0; i < f.instances.size(); ++i) {
    CHECK(f.instances[i].id == int(i + 1));
    if (i > 0) CHECK(f.instances[i].confidence <= f.instances[i - 1].confidence);
  }
}

TEST_CASE("nanodet: no person on horses.jpg") {
  const FrameDetections f = Nanodet().Detect(Photo("horses.jpg"), "horses");
  int horses = 0;
  for (const auto& d : f.instances) {
    CHECK(d.class_name != "person");
    horses += d.class_name == "horse";
  }
  CHECK(horses >= 2);
  CHECK(f.instance_ids.empty());  // nothing masked
}

TEST_CASE("nanodet: repeated detection is identical, --no-masks gives the same boxes") {
  const cv::Mat im = Photo("person.jpg");
  const FrameDetections a = Nanodet().Detect(im, "person");
  const FrameDetections b = Nanodet().Detect(im, "person");
  dynref::DetectSourceOptions o;
  o.masks = false;
  auto boxes_only = dynref::MakeDetectionSource("nanodet", o);
  CHECK(boxes_only->name() == "nanodet");
  CHECK(Nanodet().name() == "nanodet+selfie");
  CHECK(Nanodet().model_sha256() == std::string(dynref::kNanodetSha256) + "+" + dynref::kSelfieSha256);
  const FrameDetections c = boxes_only->Detect(im, "person");
  CHECK(!a.instances.empty());  // person.jpg has a person
  REQUIRE(a.instances.size() == b.instances.size());
  REQUIRE(a.instances.size() == c.instances.size());
  for (size_t i = 0; i < a.instances.size(); ++i) {
    INFO("instance " << i);
    for (const dynref::DetectedInstance* o : {&b.instances[i], &c.instances[i]}) {
      CHECK(a.instances[i].x_min == o->x_min);
      CHECK(a.instances[i].y_min == o->y_min);
      CHECK(a.instances[i].x_max == o->x_max);
      CHECK(a.instances[i].y_max == o->y_max);
      CHECK(a.instances[i].class_id == o->class_id);
      CHECK(a.instances[i].confidence == o->confidence);
    }
    CHECK_FALSE(c.instances[i].has_mask);
  }
  CHECK(cv::countNonZero(a.instance_ids != b.instance_ids) == 0);
  CHECK(c.instance_ids.empty());
}
