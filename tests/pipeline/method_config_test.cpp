// Method config: values with sources, defaults recorded, unknown keys are errors with a line.
#include <catch2/catch.hpp>
#include <fstream>

#include "core/error.h"
#include "pipeline/method_config.h"
#include "pipeline/stage_registry.h"
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
  CHECK(cfg.backbone.n_features() == 1000);
  CHECK(cfg.backbone.scale_factor() == Approx(1.2));
  for (const auto& kv : cfg.backbone.params) CHECK_FALSE(kv.second.source.empty());
  CHECK(cfg.ToJson().find("\"source\"") != std::string::npos);
}

TEST_CASE("method config: omitted backbone keys take ORB-SLAM2 defaults with a default source") {
  const MethodConfig cfg = LoadMethodConfig(Write("defaults", "method: x\nbackbone:\n  n_features: {value: 3000, source: \"paper Sec. 4\"}\n"));
  CHECK(cfg.backbone.n_features() == 3000);
  CHECK(cfg.backbone.n_levels() == 8);
  CHECK(cfg.backbone.params.at("n_levels").source.rfind("default:", 0) == 0);
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
  CHECK_THROWS_AS(CreateStages(cfg, BuiltinStageRegistry()), InputError);
}
