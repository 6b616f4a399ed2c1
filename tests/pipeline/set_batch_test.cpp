// `dynref run --set` as one batch (issue 37): order-free (features=onnx with onnx_model either
// way), list values, paths relative to the working directory, errors naming the --set argument
// and ranges that do not contradict the value.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "core/error.h"
#include "dynamic/builtin_methods.h"
#include "method/session.h"
#include "pipeline/method_config.h"
#include "test_support.h"

using namespace dynref;

namespace {

MethodConfig Sgdo() { return LoadMethodConfig(test::SourcePath("configs/sgdo.yaml")); }

std::string SetError(const std::vector<std::string>& items, const std::string& config = "configs/sgdo.yaml") {
  MethodConfig cfg = LoadMethodConfig(test::SourcePath(config));
  try {
    cfg.ApplySets(items, "dynref run --set");
    MethodRegistry registry;
    RegisterBuiltinMethods(registry);
    Session s(cfg.path, cfg.stages, registry);  // stage values are checked when the run is built
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("run --set: applied as one batch, in either order (issue 37)") {
  for (const auto& items : {std::vector<std::string>{"backbone.features=onnx", "backbone.onnx_model=models/sp.onnx"},
                            std::vector<std::string>{"backbone.onnx_model=models/sp.onnx", "backbone.features=onnx"}}) {
    MethodConfig cfg = Sgdo();
    REQUIRE_NOTHROW(cfg.ApplySets(items, "dynref run --set"));
    CHECK(cfg.backbone.extractor.type == "onnx");
    // Relative to the working directory, not to the config's folder (configs/models/...).
    CHECK(cfg.backbone.extractor.onnx.model == "models/sp.onnx");
    CHECK(cfg.backbone_params.at("onnx_model").source == "dynref run --set");
  }
}

TEST_CASE("run --set: a list value is settable (issue 37)") {
  MethodConfig cfg = Sgdo();
  cfg.ApplySets({"sgdo.mask.dynamic_classes=[person, dog]"}, "dynref run --set");
  const Param* p = nullptr;
  for (const StageConfig& sc : cfg.stages)
    if (sc.name == "sgdo.mask") p = &sc.params.params.at("dynamic_classes");
  REQUIRE(p != nullptr);
  CHECK(p->list == std::vector<std::string>{"person", "dog"});
  CHECK(SetError({"sgdo.mask.dynamic_classes=[person, dog]"}).empty());
  CHECK(SetError({"sgdo.mask.dynamic_classes=[0,1]"}) ==
        "--set sgdo.mask.dynamic_classes=[0,1]: sgdo.mask.dynamic_classes: unknown COCO class '0'");
  CHECK(SetError({"sgdo.depth.eta=[1, 2]"}) ==
        "--set sgdo.depth.eta=[1, 2]: sgdo.depth.eta: expected a single value, got a list [1, 2]");
}

TEST_CASE("run --set: errors name the --set argument and the key, ranges agree with the value (issue 37)") {
  CHECK(SetError({"backbone.mnn2_ratio=1.5"}) == "--set backbone.mnn2_ratio=1.5: backbone.mnn2_ratio: must be in (0, 1], got 1.5");
  CHECK(SetError({"sgdo.depth.lambda=inf"}) ==
        "--set sgdo.depth.lambda=inf: sgdo.depth.lambda: must be finite and in [0, 1e+06], got inf");
  CHECK(SetError({"sgdo.densemap.context_margin_m=1.5"}) ==
        "--set sgdo.densemap.context_margin_m=1.5: sgdo.densemap.context_margin_m: must be in (0, 0.2], got 1.5");
  CHECK(SetError({"mgd.probability.w_pro=nan"}, "configs/mgd.yaml") ==
        "--set mgd.probability.w_pro=nan: mgd.probability.w_pro: must be a number in [0, 10], not NaN, got nan");
  CHECK(SetError({"mgd.probability.min_velocity_px=nan"}, "configs/mgd.yaml").find("not NaN") != std::string::npos);
  CHECK(SetError({"mgd.probability.d_th_ls_px=-1"}, "configs/mgd.yaml").find("must be in (0, 1000], got -1") !=
        std::string::npos);
  CHECK(SetError({"semantic.map.grid_cell_m=inf"}, "configs/semantic.yaml").find("semantic.map.grid_cell_m: must be finite") !=
        std::string::npos);
  CHECK(SetError({"semantic.map.grid_cell_m=1e308"}, "configs/semantic.yaml").find("got 1e308") != std::string::npos);
  CHECK(SetError({"semantic.map.octree_resolution_m=inf"}, "configs/semantic.yaml").find("must be finite") !=
        std::string::npos);
  CHECK(SetError({"sgdo.densemap.keyframe_leaf_m=inf"}).find("must be finite") != std::string::npos);
  CHECK(SetError({"sgdo.nostage.eta=1"}).rfind("--set sgdo.nostage.eta=1: no stage sgdo.nostage", 0) == 0);
  CHECK(SetError({"sgdo.depth.nope=1"}) == "--set sgdo.depth.nope=1: stage sgdo.depth has no parameter nope");
  CHECK(SetError({"backbone.nope=1"}) == "--set backbone.nope=1: unknown backbone key 'nope'");
  CHECK(SetError({"eta=1"}).find("not STAGE.KEY=VALUE") != std::string::npos);
}
