// dynref synth --detections: ideal equals the ground truth; yolo-like / sparseinst-like degrade
// it by the documented kinds of error (datasets/README.md) and stay valid dynref-detections.
#include <catch2/catch.hpp>

#include "io/mask_format.h"
#include "io/sequence.h"
#include "synth/degrade.h"
#include "synth/synth.h"
#include "test_support.h"

namespace {

using namespace dynref;

double Iou(const cv::Mat& a, const cv::Mat& b) {
  const double i = cv::countNonZero(a & b), u = cv::countNonZero(a | b);
  return u > 0 ? i / u : 0.0;  // two empty masks do not match
}

}  // namespace

TEST_CASE("synth: ideal detections copy GT and degraded ones jitter and miss and stay well-formed") {
  const std::string dir = test::ScratchDir("synth_detections");
  synth::SynthOptions o;
  // 24 frames: frames 0-11 hold no missed burst on a large person (the first is frame 13).
  o.preset = "crowd", o.frames = 24, o.out = dir, o.detections = "all";
  synth::GenerateSequence(o);
  const Sequence seq = OpenSequence(dir);
  const DetectionsReader gt(dir + "/gt"), ideal(dir + "/detections/ideal"), yolo(dir + "/detections/yolo-like"),
      sparse(dir + "/detections/sparseinst-like");
  CHECK(ideal.source() == "synthetic:ideal");
  CHECK(yolo.source() == "synthetic:yolo-like");
  int gt_people = 0, yolo_people = 0, yolo_missed_people = 0;
  double yolo_iou_sum = 0;
  int yolo_iou_n = 0;
  for (const auto& f : seq.frames) {
    const FrameDetections g = gt.Read(f.rgb_stamp_text), id = ideal.Read(f.rgb_stamp_text);
    INFO("frame " << f.rgb_stamp_text);
    CHECK(!g.instances.empty());
    CHECK(id.instances.size() == g.instances.size());
    for (const auto& d : id.instances) {
      CHECK(d.confidence == 1.0);
      CHECK(Iou(id.MaskOf(d.id), g.MaskOf(d.id)) > 0.999);
    }
    const FrameDetections y = yolo.Read(f.rgb_stamp_text);
    for (const auto& e : g.instances) {
      if (e.class_id != 0 || (e.x_max - e.x_min) * (e.y_max - e.y_min) <= 5000) continue;
      ++gt_people;
      // Missed: no yolo-like person overlaps this GT person.
      bool found = false;
      for (const auto& d : y.instances)
        found |= d.class_id == 0 && Iou(y.MaskOf(d.id), g.MaskOf(e.id)) > 0.3;
      yolo_missed_people += !found;
    }
    for (const auto& d : y.instances) {
      CHECK(d.confidence < 1.0);
      CHECK(d.has_mask);
      if (d.class_id != 0 || d.confidence < 0.5) continue;  // skip false positives
      ++yolo_people;
      // Best-matching GT person.
      double best = 0;
      for (const auto& e : g.instances)
        if (e.class_id == 0) best = std::max(best, Iou(y.MaskOf(d.id), g.MaskOf(e.id)));
      yolo_iou_sum += best, ++yolo_iou_n;
    }
    (void)sparse.Read(f.rgb_stamp_text);
  }
  REQUIRE(yolo_iou_n > 10);
  const double mean_iou = yolo_iou_sum / yolo_iou_n;
  INFO("GT people " << gt_people << ", yolo-like people " << yolo_people << ", missed "
                    << yolo_missed_people << ", mean IoU " << mean_iou);
  CHECK(yolo_missed_people >= 1);
  CHECK(mean_iou > 0.6);
  CHECK(mean_iou < 0.97);  // boundary jitter and missing limbs are really there
  CHECK(yolo_people <= gt_people + 2);
}

TEST_CASE("synth: documented degradation rates") {
  const auto y = synth::ProfileFor("yolo-like"), s = synth::ProfileFor("sparseinst-like"), i = synth::ProfileFor("ideal");
  CHECK(i.miss_enter == 0);
  CHECK(i.boundary_jitter_px == 0);
  CHECK(y.miss_enter == Approx(0.03));
  CHECK(y.miss_stay == Approx(0.7));
  CHECK(y.boundary_jitter_px == 4);
  CHECK(s.limb_drop == Approx(0.25));
  CHECK(y.blur_miss_factor == Approx(3.0));
  CHECK_THROWS(synth::ProfileFor("rcnn"));
}
