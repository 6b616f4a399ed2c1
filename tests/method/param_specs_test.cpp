// Declared parameter ranges (issue 33 part 2, issue 37): every component parameter is checked
// against its spec before the first frame, at the value's own line, naming the key as written;
// NaN and infinities are refused; a component whose options live in another one is refused at
// load when that one is missing. Every registered key of every builtin component is exercised.
#include <catch2/catch.hpp>
#include <dirent.h>

#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "dynamic/builtin_methods.h"
#include "method/session.h"
#include "pipeline/method_config.h"
#include "test_support.h"

using namespace dynref;

namespace {

ParamMap StageParams(const std::vector<std::pair<std::string, std::string>>& values) {
  ParamMap m;
  m.stage_name = "t.s";
  m.file = "m.yaml";
  m.line = 3;
  int line = 5;
  for (const auto& [k, v] : values) {
    Param p;
    p.file = "m.yaml";
    p.line = line++;
    p.name = "t.s." + k;
    if (!v.empty() && v.front() == '[') {
      std::string item;
      for (char c : v.substr(1, v.size() - 2) + ",") {
        if (c == ',') {
          if (!item.empty()) p.list.push_back(item);
          item.clear();
        } else if (c != ' ') {
          item += c;
        }
      }
    } else {
      p.value = v;
    }
    m.params[k] = p;
  }
  return m;
}

const ParamSpecs kSpecs = {{RealAbove("eta", 0, 10), InfOk(Real("limit_m", 0, 5)), OddInteger("kernel_px", 1, 31),
                            Flag("on"), Choice("mode", {"a", "b"}), Names("classes")},
                           {}};

std::string Error(const ParamMap& m, const ParamSpecs& specs = kSpecs) {
  try {
    CheckParams(m, specs);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

ParamMap Valid() {
  return StageParams({{"eta", "0.1"}, {"limit_m", "2"}, {"kernel_px", "3"}, {"on", "true"}, {"mode", "a"}, {"classes", "[person]"}});
}

ParamMap With(const std::string& key, const std::string& value) {
  ParamMap m = Valid();
  Param& p = m.params.at(key);
  const ParamMap one = StageParams({{key, value}});
  p.value = one.params.at(key).value;
  p.list = one.params.at(key).list;
  return m;
}

// Sets stage.key = value in cfg's stages and expects the Session to refuse it with an InputError at
// the key's own line whose message contains `want`.
void ExpectRefusedAtKeyLine(const MethodConfig& cfg, const MethodRegistry& registry, const std::string& stage,
                            const std::string& key, const std::string& value, const std::string& want) {
  std::vector<StageConfig> stages = cfg.stages;
  int line = 0;
  for (StageConfig& sc : stages)
    if (sc.name == stage) {
      sc.params.params.at(key).value = value;
      line = sc.params.params.at(key).line;
    }
  REQUIRE(line > 0);
  try {
    Session s(cfg.path, stages, registry);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == line);
    CHECK(std::string(e.what()).find(want) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("param specs: NaN, infinities and out-of-range values name the key and its own line (issue 37)") {
  CHECK(Error(Valid()).empty());
  // eta is the first key (line 5), the stage's `- name:` line is 3.
  CHECK(Error(With("eta", "nan")) == "m.yaml:5: t.s.eta: must be a number in (0, 10], not NaN, got nan");
  CHECK(Error(With("eta", "inf")) == "m.yaml:5: t.s.eta: must be finite and in (0, 10], got inf");
  CHECK(Error(With("eta", "-inf")).find("m.yaml:5: t.s.eta: must be finite") == 0);
  CHECK(Error(With("eta", "1e308")) == "m.yaml:5: t.s.eta: must be in (0, 10], got 1e308");
  CHECK(Error(With("eta", "0")) == "m.yaml:5: t.s.eta: must be in (0, 10], got 0");
  CHECK(Error(With("eta", "-1")) == "m.yaml:5: t.s.eta: must be in (0, 10], got -1");
  // +inf only where it is declared meaningful ("no limit").
  CHECK(Error(With("limit_m", "inf")).empty());
  CHECK(Error(With("limit_m", "-inf")).find("m.yaml:6: t.s.limit_m:") == 0);
  CHECK(Error(With("kernel_px", "4")) == "m.yaml:7: t.s.kernel_px: must be an integer in 1..31 (odd), got 4");
  CHECK(Error(With("kernel_px", "1.5")) == "m.yaml:7: t.s.kernel_px: not an integer: 1.5");
  CHECK(Error(With("mode", "c")) == "m.yaml:9: t.s.mode: must be one of a | b, got 'c'");
}

TEST_CASE("param specs: type errors name the key, and a list where a scalar belongs and the reverse (issue 37)") {
  CHECK(Error(With("eta", "[1, 2]")) == "m.yaml:5: t.s.eta: expected a single value, got a list [1, 2]");
  CHECK(Error(With("eta", "")) == "m.yaml:5: t.s.eta: expected a number, got an empty value");
  CHECK(Error(With("eta", "abc")) == "m.yaml:5: t.s.eta: not a number: abc");
  CHECK(Error(With("on", "maybe")) == "m.yaml:8: t.s.on: not a boolean (true/false): maybe");
  CHECK(Error(With("classes", "person")) == "m.yaml:10: t.s.classes: expected a list of names [a, b], got 'person'");
  CHECK(Error(With("classes", "[]")).find("m.yaml:10: t.s.classes:") == 0);
  // Unknown and missing keys.
  ParamMap extra = Valid();
  extra.params["nope"] = extra.params.at("eta");
  extra.params["nope"].line = 12;
  CHECK(Error(extra) == "m.yaml:12: stage t.s: unknown parameter 'nope'");
  ParamMap missing = Valid();
  missing.params.erase("mode");
  CHECK(Error(missing) == "m.yaml:3: stage t.s: missing parameter mode");
}

TEST_CASE("param specs: an ordered pair is checked at the upper key's line") {
  const ParamSpecs specs = {{Real("min_m", 0, 10), Real("max_m", 0, 10)}, {{"min_m", "max_m"}}};
  CHECK(Error(StageParams({{"min_m", "1"}, {"max_m", "2"}}), specs).empty());
  CHECK(Error(StageParams({{"min_m", "3"}, {"max_m", "2"}}), specs) == "m.yaml:6: t.s.max_m: must be > min_m (3), got 2");
}

TEST_CASE("param specs: every builtin component declares its keys and every config passes them (issue 33)") {
  MethodRegistry registry;
  RegisterBuiltinMethods(registry);
  std::set<std::string> used;  // "stage.key" in some config
  DIR* d = opendir(test::SourcePath("configs").c_str());
  REQUIRE(d != nullptr);
  std::vector<std::string> files;
  while (const dirent* e = readdir(d)) {
    const std::string n = e->d_name;
    if (n.size() > 5 && n.substr(n.size() - 5) == ".yaml") files.push_back(n);
  }
  closedir(d);
  REQUIRE(files.size() >= 20);
  for (const std::string& f : files) {
    INFO(f);
    const MethodConfig cfg = LoadMethodConfig(test::SourcePath("configs/" + f));
    CHECK_NOTHROW(Session(cfg.path, cfg.stages, registry));
    for (const StageConfig& sc : cfg.stages)
      for (const auto& [k, p] : sc.params.params) used.insert(sc.name + "." + k);
  }
  for (const std::string& name : registry.Names()) {
    INFO(name);
    const ParamSpecs* specs = registry.FindParams(name);
    REQUIRE(specs != nullptr);  // every component declares its parameters
    for (const ParamSpec& s : specs->keys) {
      INFO(s.key);
      CHECK(used.count(name + "." + s.key) == 1);  // ... and every declared key is used by a config
      if (s.kind == ParamSpec::Kind::kReal) CHECK(s.lo <= s.hi);
    }
  }
}

TEST_CASE("param specs: mgd.boxes without mgd.probability is refused when the run is built (issue 33)") {
  MethodRegistry registry;
  RegisterBuiltinMethods(registry);
  MethodConfig cfg = LoadMethodConfig(test::SourcePath("configs/mgd.yaml"));
  std::vector<StageConfig> stages;
  int boxes_line = 0;
  for (const StageConfig& sc : cfg.stages)
    if (sc.name != "mgd.probability") stages.push_back(sc);
  for (const StageConfig& sc : stages)
    if (sc.name == "mgd.boxes") boxes_line = sc.params.line;
  try {
    Session s(cfg.path, stages, registry);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == boxes_line);
    CHECK(std::string(e.what()).find("stage mgd.boxes needs mgd.probability in the stage list") != std::string::npos);
  }
}

TEST_CASE("param specs: epi.enhance down below 0.05 is refused at its line (issue 37, config fuzzer)") {
  // scripts/fuzz.sh configs: down = 1e-308 passed (0, 1) and cv::resize asserted on frame 0 (an
  // empty two-scale image); 0.05 keeps >= 2 px of the smallest frame `dynref run` accepts (64x48).
  MethodRegistry registry;
  RegisterBuiltinMethods(registry);
  const MethodConfig cfg = LoadMethodConfig(test::SourcePath("configs/epi.yaml"));
  for (const char* value : {"1e-308", "0.0001", "0.049"}) {
    INFO(value);
    ExpectRefusedAtKeyLine(cfg, registry, "epi.enhance", "down", value,
                           "epi.enhance.down: must be in [0.05, 1), got " + std::string(value));
  }
  std::vector<StageConfig> ok = cfg.stages;
  for (StageConfig& sc : ok)
    if (sc.name == "epi.enhance") sc.params.params.at("down").value = "0.05";
  CHECK_NOTHROW(Session(cfg.path, ok, registry));
}

TEST_CASE("param specs: an even LK window or border_px 0 is refused at the key's line, not the stage's (issue 37)") {
  // scripts/fuzz.sh configs: sgdo.coarse lk_window_px=32 and border_px=0 passed the specs and
  // LkOptions::Check refused them at the `- name:` line as "window_px" / "border_px must be >= 1".
  MethodRegistry registry;
  RegisterBuiltinMethods(registry);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"sgdo", "sgdo.coarse"}, {"epi", "epi.vote"}};
  for (const auto& [method, stage] : cases) {
    const MethodConfig cfg = LoadMethodConfig(test::SourcePath("configs/" + method + ".yaml"));
    for (const auto& [key, value, want] : std::vector<std::tuple<std::string, std::string, std::string>>{
             {"lk_window_px", "32", "must be an integer in 3..101 (odd), got 32"},
             {"border_px", "0", "must be an integer in 1..1000, got 0"}}) {
      INFO(stage << "." << key << "=" << value);
      ExpectRefusedAtKeyLine(cfg, registry, stage, key, value, stage + "." + key + ": " + want);
    }
  }
}
