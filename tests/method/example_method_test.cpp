// A tiny method defined entirely in this test file (issue 12, "adding a method touches only
// ref/dynamic/<method>/, configs/ and tests/"): a before-extraction stage that blanks a region
// of the grey image, a stage that excludes the features in a fixed box, and a map module that
// writes one file at the end of the run. Registered into a registry passed to the run; the
// pipeline is not edited.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "pipeline/pipeline.h"
#include "synth/synth.h"
#include "test_support.h"
#include "trace/trace_reader.h"

using namespace dynref;

namespace {

struct Box {
  double x0, y0, x1, y1;
  bool Contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

Box ReadBox(const ParamMap& p) {
  p.RequireKnownKeys({"x0", "y0", "x1", "y1"});
  return {p.GetDouble("x0"), p.GetDouble("y0"), p.GetDouble("x1"), p.GetDouble("y1")};
}

class BlackoutStage : public Stage {
 public:
  explicit BlackoutStage(const ParamMap& p) : box_(ReadBox(p)) {}
  std::string name() const override { return "example.blackout"; }
  Hook hook() const override { return Hook::kBeforeExtraction; }
  void Run(StageContext& ctx) override {
    const cv::Rect r(cv::Point(int(box_.x0), int(box_.y0)), cv::Point(int(box_.x1), int(box_.y1)));
    ctx.frame.grey_for_extraction()(r).setTo(0);
  }

 private:
  Box box_;
};

class BoxExcludeStage : public Stage {
 public:
  explicit BoxExcludeStage(const ParamMap& p) : box_(ReadBox(p)) {}
  std::string name() const override { return "example.box"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override {
    const Frame& f = ctx.frame.view();
    for (size_t i = 0; i < f.N(); ++i)
      if (box_.Contains(f.keys[i].pt.x, f.keys[i].pt.y)) ctx.frame.Exclude(static_cast<int>(i), name(), "in-box");
  }

 private:
  Box box_;
};

// Counts keyframes as they come and writes the final keyframe poses' count at the end.
class KeyframeCountModule : public MapModule {
 public:
  explicit KeyframeCountModule(const ParamMap& p) : fail_(p.GetBool("fail")) {}
  std::string name() const override { return "example.kfcount"; }
  void OnKeyFrame(const MapModuleContext&) override { ++seen_; }
  void Finish(const Map& map, RunEnd& end) override {
    if (fail_) throw std::runtime_error("cannot write keyframe_count.txt (test)");
    int live = 0;
    for (const auto& kv : map.keyframes) live += kv.second->bad ? 0 : 1;
    const std::string path = end.out_dir() + "/keyframe_count.txt";
    AtomicWriteFile(path, std::to_string(seen_) + " created, " + std::to_string(live) + " kept\n");
    end.AddOutput(name(), path, "keyframe count");
  }

 private:
  bool fail_;
  int seen_ = 0;
};

MethodRegistry ExampleRegistry() {
  MethodRegistry r;
  r.AddStage("example.blackout", [](const ParamMap& p, SharedState&) { return std::make_unique<BlackoutStage>(p); });
  r.AddStage("example.box", [](const ParamMap& p, SharedState&) { return std::make_unique<BoxExcludeStage>(p); });
  r.AddMapModule("example.kfcount",
                 [](const ParamMap& p, SharedState&) { return std::make_unique<KeyframeCountModule>(p); });
  return r;
}

std::string Config(const std::string& dir, bool fail) {
  auto box = [](int x0, int y0, int x1, int y1) {
    auto v = [](int n) { return "{value: " + std::to_string(n) + ", source: \"test\"}"; };
    return "{x0: " + v(x0) + ", y0: " + v(y0) + ", x1: " + v(x1) + ", y1: " + v(y1) + "}";
  };
  return test::WriteText(dir + "/example.yaml",
                         "method: example\nstages:\n"
                         "  - name: example.blackout\n    params: " + box(400, 300, 600, 460) + "\n"
                         "  - name: example.box\n    params: " + box(0, 0, 200, 150) + "\n"
                         "  - name: example.kfcount\n    params: {fail: {value: " + std::string(fail ? "true" : "false") +
                             ", source: \"test\"}}\n");
}

// Each test case synthesises its own copy (CTest runs test cases in parallel processes).
std::string ExampleSequence(const std::string& dir) {
  synth::SynthOptions so;
  so.preset = "static_xyz";
  so.frames = 12;
  so.seed = 2;
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  return so.out;
}

RunOptions ExampleRun(const std::string& dir, const MethodRegistry& registry, bool fail) {
  RunOptions o;
  o.sequence = ExampleSequence(dir);
  o.out_dir = dir + "/run";
  o.method = "example";
  o.config_path = Config(dir, fail);
  o.registry = &registry;
  o.trace_level = "full";
  o.progress = false;
  return o;
}

}  // namespace

TEST_CASE("example method: stages and a map module plugged in without touching the pipeline") {
  const std::string dir = test::ScratchDir("example_method");
  const MethodRegistry registry = ExampleRegistry();
  const RunOptions o = ExampleRun(dir, registry, false);
  const RunResult r = RunSequence(o);
  REQUIRE(r.exit_code == 0);
  REQUIRE(r.tracked == 12);

  // Features in the box are excluded (and only those), none survive in the blanked region.
  const Box box{0, 0, 200, 150}, black{420, 320, 580, 440};
  trace::TraceReader reader(o.out_dir + "/trace.dtr");
  int in_box = 0, excluded = 0, wrongly_excluded = 0, in_black = 0, keys = 0;
  for (size_t g = 0; g < reader.groups().size(); ++g) {
    std::map<int64_t, std::pair<double, double>> obs;
    std::set<std::string> rejected;
    for (const trace::Record& rec : reader.ReadGroup(g)) {
      if (rec.type == trace::RecordType::kObservation) obs[rec.feature_index] = {rec.u, rec.v};
      if (rec.type == trace::RecordType::kDecision && rec.stage == "example.box" && !rec.kept) rejected.insert(rec.entity);
    }
    for (const auto& [i, uv] : obs) {
      ++keys;
      const std::string id = "f" + std::to_string(reader.groups()[g].frame) + "." + std::to_string(i);
      const bool inside = box.Contains(uv.first, uv.second);
      in_box += inside;
      excluded += rejected.count(id) > 0;
      wrongly_excluded += !inside && rejected.count(id);
      in_black += black.Contains(uv.first, uv.second);
    }
  }
  INFO("keys " << keys << " in box " << in_box << " excluded " << excluded);
  CHECK(keys > 1000);
  CHECK(in_box > 20);  // the synthetic room is textured there: the box has work to do
  CHECK(excluded == in_box);
  CHECK(wrongly_excluded == 0);
  CHECK(in_black == 0);

  // The map module's file is written and listed in run.json.
  std::ifstream in(o.out_dir + "/run.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  REQUIRE(j["outputs"].size() == 1);
  CHECK(j["outputs"][0]["module"] == "example.kfcount");
  CHECK(j["output_errors"].empty());
  const std::string count = test::ReadFileBytes(o.out_dir + "/keyframe_count.txt");
  CHECK(count.find(" created, ") != std::string::npos);
  CHECK(count.rfind(std::to_string(j["keyframes"].get<int>()) + " kept") != std::string::npos);
}

TEST_CASE("example method: a failed end-of-run write ends the run in error, named in run.json") {
  const std::string dir = test::ScratchDir("example_method_fail");
  const MethodRegistry registry = ExampleRegistry();
  const RunOptions o = ExampleRun(dir, registry, true);
  const RunResult r = RunSequence(o);
  CHECK(r.exit_code == 2);
  CHECK(r.end_state == "error: output example.kfcount: cannot write keyframe_count.txt (test)");
  std::ifstream in(o.out_dir + "/run.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  CHECK(j["end_state"] == r.end_state);
  CHECK(j["output_errors"].size() == 1);
  CHECK_FALSE(std::filesystem::exists(o.out_dir + "/keyframe_count.txt"));
}
