// The per-run Session (issue 12): components created fresh per run from a registry, per-run
// SharedState, config order at each hook, landmark events forwarded, outputs and errors of
// Finish collected (one failing component does not stop the others).
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "method/session.h"

using namespace dynref;

namespace {

// Appends "<name>@<hook>" to a log shared through the run's SharedState.
struct Log {
  std::vector<std::string> lines;
};

class LoggingStage : public Stage {
 public:
  LoggingStage(std::string name, Hook hook, std::shared_ptr<Log> log) : name_(std::move(name)), hook_(hook), log_(std::move(log)) {}
  std::string name() const override { return name_; }
  Hook hook() const override { return hook_; }
  void Run(StageContext&) override { log_->lines.push_back(name_ + "@" + HookName(hook_)); }
  void OnLandmarkEvent(const LandmarkEvent& e) override {
    log_->lines.push_back(name_ + ":" + LandmarkEventName(e.kind) + ":" + std::to_string(e.landmark.id) + ">" +
                          std::to_string(e.by_id));
  }
  void Finish(RunEnd& end) override {
    if (name_ == "t.fail") throw std::runtime_error("disk full");
    end.AddOutput(name_, end.out_dir() + "/" + name_ + ".txt", "a test file");
  }

 private:
  std::string name_;
  Hook hook_;
  std::shared_ptr<Log> log_;
};

MethodRegistry TestRegistry() {
  MethodRegistry r;
  auto add = [&](const std::string& name, Hook hook) {
    r.AddStage(name, [name, hook](const ParamMap&, SharedState& shared) -> std::unique_ptr<Stage> {
      return std::make_unique<LoggingStage>(name, hook, shared.Get<Log>("log"));
    });
  };
  add("t.a", Hook::kAfterExtraction);
  add("t.b", Hook::kBeforeInitialPose);
  add("t.c", Hook::kAfterExtraction);
  add("t.fail", Hook::kOnMapUpdate);
  return r;
}

std::vector<StageConfig> Components(const std::vector<std::string>& names) {
  std::vector<StageConfig> out;
  int line = 3;
  for (const std::string& n : names) {
    StageConfig sc;
    sc.name = n;
    sc.params.stage_name = n;
    sc.params.line = line++;
    out.push_back(sc);
  }
  return out;
}

}  // namespace

TEST_CASE("session: stages run at their hook in config order, state is per session") {
  const MethodRegistry registry = TestRegistry();
  Session s1("m.yaml", Components({"t.c", "t.b", "t.a"}), registry);
  Session s2("m.yaml", Components({"t.a"}), registry);
  CHECK(s1.stage_count() == 3);
  Frame f;
  Map map;
  Camera cam;
  trace::TraceWriter tr("", trace::Level::kOff, trace::RunHeader{});
  FrameEdit edit(f, map, Hook::kAfterExtraction);
  StageContext ctx{edit, nullptr, nullptr, map, cam, tr};
  s1.Run(Hook::kAfterExtraction, ctx);
  s1.Run(Hook::kBeforeInitialPose, ctx);
  CHECK(edit.hook() == Hook::kBeforeInitialPose);  // the session sets the handle's hook
  s2.Run(Hook::kAfterExtraction, ctx);
  const auto& log1 = s1.shared().Get<Log>("log")->lines;
  CHECK(log1 == std::vector<std::string>{"t.c@after_extraction", "t.a@after_extraction", "t.b@before_initial_pose"});
  // The second session has its own log: it never sees the first one's entries.
  CHECK(s2.shared().Get<Log>("log")->lines == std::vector<std::string>{"t.a@after_extraction"});
}

TEST_CASE("session: an unknown component names the config line and lists the known ones") {
  const MethodRegistry registry = TestRegistry();
  try {
    Session s("m.yaml", Components({"t.a", "t.nope"}), registry);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == 4);
    CHECK(std::string(e.what()).find("unknown stage 't.nope' (known: t.a, t.b, t.c, t.fail)") != std::string::npos);
  }
  MethodRegistry r = TestRegistry();
  CHECK_THROWS_AS(r.AddStage("t.a", nullptr), std::logic_error);
}

TEST_CASE("session: landmark events from the map reach every component") {
  const MethodRegistry registry = TestRegistry();
  Session s("m.yaml", Components({"t.a", "t.b"}), registry);
  Map map;
  map.AddObserver(&s);
  map.NewMapPoint(Eigen::Vector3d(0, 0, 1), 0, 0);
  map.NewMapPoint(Eigen::Vector3d(0, 0, 2), 0, 0);
  map.ReplacePoint(0, 1);
  map.SetBadPoint(1);
  map.SetBadPoint(1);  // already bad: no second event
  map.RemoveObserver(&s);
  map.NewMapPoint(Eigen::Vector3d(0, 0, 3), 0, 0);  // not observed any more
  CHECK(s.shared().Get<Log>("log")->lines ==
        std::vector<std::string>{"t.a:created:0>-1", "t.b:created:0>-1", "t.a:created:1>-1", "t.b:created:1>-1",
                                 "t.a:replaced:0>1", "t.b:replaced:0>1", "t.a:culled:1>-1", "t.b:culled:1>-1"});
}

TEST_CASE("session: Finish collects outputs and errors, one failure does not stop the others") {
  const MethodRegistry registry = TestRegistry();
  Session s("m.yaml", Components({"t.a", "t.fail", "t.b"}), registry);
  const Map map;
  const SessionEnd end = s.Finish(map, "/run");
  REQUIRE(end.outputs.size() == 2);
  CHECK(end.outputs[0].path == "t.a.txt");  // relative to the run folder
  CHECK(end.outputs[1].path == "t.b.txt");
  CHECK(end.errors == std::vector<std::string>{"t.fail: disk full"});
}

TEST_CASE("shared state: one object per key and type") {
  SharedState s;
  auto a = s.Get<Log>("x");
  a->lines.push_back("1");
  CHECK(s.Get<Log>("x")->lines.size() == 1);
  CHECK(s.Has("x"));
  CHECK_FALSE(s.Has("y"));
  CHECK_THROWS_AS(s.Get<int>("x"), std::logic_error);
}
