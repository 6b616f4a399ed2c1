// WithTemporalLinks (issue 39 item 3): the detector of `dynref run --detector` passes its frames
// through the same linker as `dynref detect --temporal-gap`, keeping the inner source's name.
#include <catch2/catch.hpp>
#include <map>

#include "core/error.h"
#include "detect/temporal_source.h"

using namespace dynref;

namespace {

// Scripted source: one person box per stamp listed, nobody otherwise.
class ScriptedSource : public DetectionSource {
 public:
  explicit ScriptedSource(std::map<std::string, double> x_by_stamp) : x_(std::move(x_by_stamp)) {}
  std::string name() const override { return "nanodet"; }
  std::string model_sha256() const override { return "abc"; }
  bool needs_image() const override { return false; }
  FrameDetections Detect(const cv::Mat&, const std::string& stamp_text) override {
    FrameDetections f;
    f.stamp_text = stamp_text;
    const auto it = x_.find(stamp_text);
    if (it == x_.end()) return f;
    DetectedInstance d;
    d.id = 1;
    d.class_id = 0;
    d.class_name = "person";
    d.confidence = 0.4;
    d.x_min = it->second;
    d.y_min = 100;
    d.x_max = it->second + 100;
    d.y_max = 300;
    f.instances.push_back(d);
    return f;
  }

 private:
  std::map<std::string, double> x_;
};

}  // namespace

TEST_CASE("detect: a run's detector carries a missed person through the temporal linker") {
  detect::TemporalOptions o;
  o.max_gap = 2;
  auto src = detect::WithTemporalLinks(
      std::make_unique<ScriptedSource>(std::map<std::string, double>{{"1.0", 100}, {"1.1", 110}, {"1.2", 120}}), o,
      cv::Size(640, 480));
  CHECK(src->name() == "nanodet");  // the score scale stays the detector's
  CHECK(src->model_sha256() == "abc");
  CHECK_FALSE(src->needs_image());
  for (const char* s : {"1.0", "1.1", "1.2"}) CHECK(src->Detect({}, s).instances.size() == 1);
  // Missed at 1.3 and 1.4: carried along the corner line (x_min 130, 140), box only; gone at 1.5.
  for (const auto& [stamp, x] : std::map<std::string, double>{{"1.3", 130}, {"1.4", 140}}) {
    const FrameDetections f = src->Detect({}, stamp);
    REQUIRE(f.instances.size() == 1);
    CHECK(f.instances[0].x_min == Approx(x));
    CHECK(f.instances[0].confidence == Approx(0.4));
    CHECK_FALSE(f.instances[0].has_mask);
  }
  CHECK(src->Detect({}, "1.5").instances.empty());
  CHECK_THROWS_AS(src->Detect({}, "frame7"), InputError);  // the linker needs a numeric stamp

  // Gap 0 is the source itself; a bad option is refused.
  o.max_gap = 0;
  CHECK(detect::WithTemporalLinks(std::make_unique<ScriptedSource>(std::map<std::string, double>{}), o,
                                  cv::Size(640, 480))->Detect({}, "1.0").instances.empty());
  o.max_gap = -1;
  CHECK_THROWS_AS(detect::WithTemporalLinks(std::make_unique<ScriptedSource>(std::map<std::string, double>{}), o,
                                            cv::Size(640, 480)),
                  std::invalid_argument);
}
