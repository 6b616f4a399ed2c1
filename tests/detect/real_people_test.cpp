// Issue 39 end to end on real people: 3 real TUM fr3 walking_halfsphere frames
// (datasets/real/tum_fr3_walking_halfsphere_3frames, one motion-blurred) against the hand boxes;
// blur and mgd use the people NanoDet finds (calibrated threshold), report what they used and
// dropped, and warn when the paper's raw threshold drops most of them.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/format.h"
#include "test_support.h"

using dynref::test::Quote;
using dynref::test::ReadFileBytes;
using dynref::test::RunDynref;
using dynref::test::ScratchDir;
using dynref::test::SourcePath;

namespace {

const std::string kRealSeq = SourcePath("datasets/real/tum_fr3_walking_halfsphere_3frames");
const std::string kBoxes = SourcePath("datasets/real/tum_fr3_walking_halfsphere_10rgb_person_boxes.txt");

// Detections of the 3 frames, made by each test case in its own folder: CTest runs the test cases
// as parallel processes, and one shared folder was wiped by one while the other read it.
std::string Detections(const std::string& user) {
  const std::string d = ScratchDir("real_people_det_" + user) + "/det";
  const auto r = RunDynref("detect --source nanodet --sequence " + Quote(kRealSeq) + " --camera tum_fr3 --out " + Quote(d));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  return d;
}

nlohmann::json RunJson(const std::string& run_dir) { return nlohmann::json::parse(ReadFileBytes(run_dir + "/run.json")); }

}  // namespace

TEST_CASE("real people: dynref info prints NanoDet's person scores and recall against the hand boxes", "[cli]") {
  const auto r = RunDynref("info " + Quote(Detections("info")) + " --boxes " + Quote(kBoxes));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("source         nanodet+selfie"));
  CHECK_THAT(r.output, Catch::Contains("calibration    nanodet"));
  CHECK_THAT(r.output, Catch::Contains("  person  2  "));  // one person in each sharp frame
  // The hand boxes hold 20 persons over 10 frames; the folder covers 3 of them (6 persons).
  CHECK_THAT(r.output, Catch::Contains("conf >= 0.30  recall 2/20"));
  CHECK_THAT(r.output, Catch::Contains("precision 2/2 = 1.000"));
}

TEST_CASE("real people: blur and mgd use NanoDet's people at the calibrated threshold and warn at the raw one", "[cli]") {
  const std::string dir = ScratchDir("real_people_run");
  const std::string detections = Detections("run");
  for (const std::string method : {"blur", "mgd"}) {
    INFO(method);
    const std::string stage = method == "blur" ? "blur.mask" : "mgd.boxes";
    const std::string scale_key = method == "blur" ? "blur.mask.threshold_scale" : "mgd.probability.threshold_scale";
    const std::string base = "run --method " + method + " --sequence " + Quote(kRealSeq) + " --camera tum_fr3 --detections " +
                             Quote(detections) + " --no-progress --out ";
    const auto cal = RunDynref(base + Quote(dir + "/" + method + "_cal"));
    INFO(cal.output);
    REQUIRE(cal.exit_code == 0);
    CHECK_THAT(cal.output, Catch::Contains("detections: " + stage + " "));
    CHECK_THAT(cal.output, !Catch::Contains("warning"));
    const nlohmann::json j = RunJson(dir + "/" + method + "_cal");
    REQUIRE(j["detections_used"].size() == 1);
    const nlohmann::json& u = j["detections_used"][0];
    CHECK(u["stage"] == stage);
    CHECK(u["source"] == "nanodet+selfie");
    CHECK(u["seen"].get<int>() >= 2);  // the two persons (mgd also counts chairs)
    CHECK(2 * u["dropped"].get<int>() <= u["seen"].get<int>());
    CHECK(u["paper_threshold"] == 0.5);
    CHECK(u["applied_threshold"] == 0.25);  // NanoDet's equivalent of the papers' 0.5
    CHECK(j["warnings"].empty());

    const auto raw = RunDynref(base + Quote(dir + "/" + method + "_raw") + " --set " + scale_key + "=raw");
    INFO(raw.output);
    REQUIRE(raw.exit_code == 0);
    CHECK_THAT(raw.output, Catch::Contains("warning: " + stage + " dropped "));
    const nlohmann::json w = RunJson(dir + "/" + method + "_raw");
    CHECK(w["detections_used"][0]["applied_threshold"] == 0.5);
    CHECK(w["detections_used"][0]["seen"] == u["seen"]);
    CHECK(2 * w["detections_used"][0]["dropped"].get<int>() > u["seen"].get<int>());
    REQUIRE(w["warnings"].size() == 1);
    CHECK_THAT(w["warnings"][0].get<std::string>(), Catch::Contains("min_confidence"));
  }
}

TEST_CASE("real people: --temporal-gap carries the person NanoDet misses in the motion-blurred frame", "[cli]") {
  const std::string d = ScratchDir("real_people_temporal") + "/det";
  const auto r = RunDynref("detect --source nanodet --no-masks --temporal-gap 2 --sequence " + Quote(kRealSeq) +
                           " --camera tum_fr3 --out " + Quote(d));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string tracks = ReadFileBytes(d + "/tracks.txt");
  CHECK_THAT(tracks, Catch::Contains(" carried"));
  CHECK_THAT(tracks, Catch::Contains("1341846434.846345 "));
  const auto info = RunDynref("info " + Quote(d) + " --boxes " + Quote(kBoxes));
  INFO(info.output);
  CHECK_THAT(info.output, Catch::Contains("conf >= 0.30  recall 3/20"));
}
