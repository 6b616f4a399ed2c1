// `dynref run --detector SPEC --detector-temporal-gap N` (issue 39 item 3): the run's detector
// passes through the temporal linker of `dynref detect --temporal-gap`, run.json names it, and the
// option is refused without a detector or out of range.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>
#include <string>

#include "synth/synth.h"
#include "test_support.h"

using namespace dynref;

namespace {

int SeenTotal(const nlohmann::json& run) {
  int seen = 0;
  for (const auto& u : run.at("detections_used")) seen += u.at("seen").get<int>();
  return seen;
}

}  // namespace

TEST_CASE("run: --detector-temporal-gap links the detector's frames and run.json says so end to end", "[cli]") {
  const std::string dir = test::ScratchDir("run_detector_temporal");
  synth::SynthOptions so;
  so.preset = "walking_xyz";
  so.frames = 12;
  so.seed = 3;
  so.detections = "yolo-like";
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  const std::string base = "run --method sgdo --sequence " + test::Quote(so.out) + " --trace off --no-progress";
  const test::CommandResult plain = test::RunDynref(base + " --out " + test::Quote(dir + "/plain") + " --detector gt:yolo-like");
  INFO(plain.output);
  REQUIRE(plain.exit_code == 0);
  const test::CommandResult linked = test::RunDynref(base + " --out " + test::Quote(dir + "/linked") +
                                                     " --detector gt:yolo-like --detector-temporal-gap 2");
  INFO(linked.output);
  REQUIRE(linked.exit_code == 0);
  const auto a = nlohmann::json::parse(test::ReadFileBytes(dir + "/plain/run.json"));
  const auto b = nlohmann::json::parse(test::ReadFileBytes(dir + "/linked/run.json"));
  CHECK(a.at("detector").get<std::string>().find("temporal") == std::string::npos);
  CHECK(b.at("detector").get<std::string>().find("temporal-gap:2 temporal-iou:0.29999999999999999") != std::string::npos);
  CHECK(SeenTotal(b) >= SeenTotal(a));  // carried boxes only add detections

  const std::string out = " --out " + test::Quote(dir + "/bad");
  const test::CommandResult no_detector = test::RunDynref(base + out + " --detector-temporal-gap 2");
  CHECK(no_detector.exit_code == 2);
  CHECK(no_detector.output.find("--detector-temporal-gap") != std::string::npos);
  const test::CommandResult bad_gap = test::RunDynref(base + out + " --detector gt:yolo-like --detector-temporal-gap 99");
  CHECK(bad_gap.exit_code == 2);
  CHECK(bad_gap.output.find("max_gap must be in 0..30") != std::string::npos);
}
