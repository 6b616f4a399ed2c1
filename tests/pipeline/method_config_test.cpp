// Method config: values with sources, defaults recorded, unknown keys are errors with a line.
#include <catch2/catch.hpp>
#include <fstream>

#include "core/error.h"
#include "pipeline/method_config.h"
#include "dynamic/builtin_methods.h"
#include "method/session.h"
#include "test_support.h"

using namespace dynref;

namespace {
std::string Write(const std::string& name, const std::string& text) {
  const std::string path = test::ScratchDir("method_config_" + name) + "/c.yaml";
  std::ofstream(path) << text;
  return path;
}
}  // namespace

TEST_CASE("method config: configs/orb.yaml loads with every value sourced") {
  const MethodConfig cfg = LoadMethodConfig(test::SourcePath("configs/orb.yaml"));
  CHECK(cfg.method == "orb");
  CHECK(cfg.stages.empty());
  CHECK(cfg.backbone.orb.n_features == 1000);
  CHECK(cfg.backbone.orb.scale_factor == 1.2);
  CHECK(cfg.backbone_params.size() == BackboneKeys().size());
  for (const auto& kv : cfg.backbone_params) CHECK_FALSE(kv.second.source.empty());
  CHECK(cfg.ToJson().find("\"source\"") != std::string::npos);
}

TEST_CASE("method config: omitted backbone keys take ORB-SLAM2 defaults with a default source") {
  const MethodConfig cfg = LoadMethodConfig(Write("defaults", "method: x\nbackbone:\n  n_features: {value: 3000, source: \"paper Sec. 4\"}\n"));
  CHECK(cfg.backbone.orb.n_features == 3000);
  CHECK(cfg.backbone.orb.n_levels == 8);
  CHECK(cfg.backbone_params.at("n_levels").source.rfind("default:", 0) == 0);
}

TEST_CASE("method config: unknown keys, missing sources and unknown stages are errors with file:line") {
  const std::string bad_key = Write("badkey", "method: x\nbackbone:\n  n_feature: {value: 1, source: s}\n");
  try {
    LoadMethodConfig(bad_key);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == 3);
    CHECK(std::string(e.what()).find("n_feature") != std::string::npos);
  }
  CHECK_THROWS_AS(LoadMethodConfig(Write("nosource", "method: x\nbackbone:\n  n_features: {value: 1}\n")), InputError);
  CHECK_THROWS_AS(LoadMethodConfig(Write("top", "method: x\nbackbon: {}\n")), InputError);
  CHECK_THROWS_AS(LoadMethodConfig(Write("range", "method: x\nbackbone:\n  n_levels: {value: 0, source: s}\n")), InputError);
  const MethodConfig cfg = LoadMethodConfig(Write("stage", "method: x\nstages:\n  - name: nope.stage\n    params: {}\n"));
  MethodRegistry registry;
  RegisterBuiltinMethods(registry);
  CHECK_THROWS_AS(Session(cfg.path, cfg.stages, registry), InputError);
}

TEST_CASE("method config: out-of-range backbone integers are errors with file:line") {
  struct Case {
    std::string line, fragment;
  };
  const Case cases[] = {
      {"n_features: {value: 99999999999, source: s}", "backbone.n_features: must be in 1..100000"},
      {"n_features: {value: 1e300, source: s}", "backbone.n_features: must be in 1..100000"},
      {"n_features: {value: 0, source: s}", "backbone.n_features: must be in 1..100000"},
      {"n_levels: {value: 17, source: s}", "backbone.n_levels: must be in 1..16"},
      {"ini_th_fast: {value: 256, source: s}", "backbone.ini_th_fast: must be in 1..255"},
      {"min_init_points: {value: 4294967796, source: s}", "backbone.min_init_points: must be in"},
      {"max_frames: {value: 2147483647, source: s}", "backbone.max_frames: must be in 1..100000"},
      {"reloc_recent_keyframes: {value: -1, source: s}", "backbone.reloc_recent_keyframes: must"},
      {"seed: {value: 1e30, source: s}", "backbone.seed: must be in 0..9007199254740992"},
      {"n_features: {value: 10.5, source: s}", "backbone.n_features: not an integer: 10.5"},
  };
  int n = 0;
  for (const Case& c : cases) {
    const std::string path =
        Write("int_range" + std::to_string(n++), "method: x\nbackbone:\n  " + c.line + "\n");
    INFO(c.line);
    try {
      LoadMethodConfig(path);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find(path + ":3: " + c.fragment) != std::string::npos);
    }
  }
  // The bounds admit the shipped configs and the ORB-SLAM2 defaults.
  const std::string max =
      Write("int_max", "method: x\nbackbone:\n  n_features: {value: 100000, source: s}\n");
  CHECK(LoadMethodConfig(max).backbone.orb.n_features == 100000);
}

TEST_CASE("method config: duplicate keys and a stage listed twice are errors with file:line") {
  struct Case {
    std::string text, fragment;
    int line;
  };
  const Case cases[] = {
      {"method: x\nmethod: y\n", "duplicate key 'method' (first given at line 1)", 2},
      {"method: x\nbackbone:\n  n_features: {value: 1000, source: s}\n"
       "  n_features: {value: 2000, source: s}\n",
       "backbone: duplicate key 'n_features' (first given at line 3)", 4},
      {"method: x\nbackbone:\n  n_features: {value: 1000, value: 2000, source: s}\n",
       "n_features: duplicate key 'value'", 3},
      {"method: x\nstages:\n  - name: sgdo.mask\n    params: {}\n"
       "  - name: sgdo.mask\n    params: {}\n",
       "stage 'sgdo.mask' listed twice (first at line 3)", 5},
      {"method: x\nstages:\n  - name: sgdo.mask\n    params:\n      a: {value: 1, source: s}\n"
       "      a: {value: 2, source: s}\n",
       "sgdo.mask: duplicate key 'a' (first given at line 5)", 6},
      {"method: x\nstages:\n  - name: sgdo.mask\n    name: sgdo.depth\n",
       "stage: duplicate key 'name'", 4},
      // Fuzz findings (scripts/fuzz.sh): keys that are maps or lists made yaml-cpp throw a bare
      // "bad conversion"; they are named now.
      {"method: x\n{a: 1}: 2\n", "a key must be a plain name, not a map or a list", 2},
      {"method: x\nbackbone:\n  [n_features]: {value: 1000, source: s}\n",
       "a key must be a plain name, not a map or a list", 3},
      {"method: x\nstages:\n  - name: sgdo.mask\n    params:\n      {a: b}: {value: 1, source: s}\n",
       "a key must be a plain name, not a map or a list", 5},
  };
  int n = 0;
  for (const Case& c : cases) {
    const std::string path = Write("dup" + std::to_string(n++), c.text);
    INFO(c.text);
    try {
      LoadMethodConfig(path);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.line() == c.line);
      CHECK(std::string(e.what()).find(c.fragment) != std::string::npos);
    }
  }
  // No shipped config lists a stage or a key twice.
  for (const char* name : {"orb", "sgdo", "sgdo_G", "sgdo_O", "sgdo_S", "sgdo_SG", "sgdo_SGD",
                           "sgdo_SGO", "sgdo_vote"})
    CHECK_NOTHROW(LoadMethodConfig(MethodConfigPath(name)));
}

TEST_CASE("method config: a directory or a missing file as config is an error naming the path", "[cli]") {
  const std::string dir = test::ScratchDir("method_config_dir");
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(LoadMethodConfig(dir), Contains(dir + ": method config is not a regular file"));
  CHECK_THROWS_WITH(LoadMethodConfig(dir + "/nope.yaml"),
                    Contains(dir + "/nope.yaml: method config not found"));
  test::ExpectBadInput("run --config " + test::Quote(dir) + " --sequence " +
                           test::Quote(test::SourcePath("datasets/real/tum_fr1_desk_9frames")) +
                           " --out " + test::Quote(dir + "/out"),
                       dir + ": method config is not a regular file");
}
