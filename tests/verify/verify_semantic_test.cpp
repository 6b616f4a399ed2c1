// Tests of the semantic verifiers (ref/verify/README.md): hand-built records recomputed, planted
// wrong records refused.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "test_support.h"
#include "verify_test_support.h"
#include "trace/trace_reader.h"
#include "trace/trace_writer.h"
#include "verify/verifier.h"
#include "verify/verify_run.h"

namespace {

using dynref::trace::EntityKind;
using dynref::trace::NamedValue;
using Inputs = std::vector<NamedValue>;

struct SemanticPlant {
  std::string stage, entity;
  std::string drop_input;
  double after_delta = 0;
  std::string reason;  // for stage "semantic.mask.decision"
};

nlohmann::json SemanticParam(const nlohmann::json& v) { return {{"value", v}, {"source", "test"}}; }

std::string SemanticConfig() {
  nlohmann::json c;
  c["method"] = "semantic";
  c["stages"] = nlohmann::json::array(
      {{{"name", "semantic.mask"},
        {"params",
         {{"prior_dynamic_classes", SemanticParam({"person", "dog"})}, {"min_confidence", SemanticParam("0.25")},
          {"d_max_px", SemanticParam("6")}, {"t_int_m", SemanticParam("0.3")}, {"interaction", SemanticParam("true")},
          {"dilation_kernel_px", SemanticParam("1")}, {"reject_keypoints", SemanticParam("true")}}}}});
  return c.dump();
}

// Frame 2: a person (1), a chair touching it (3: non-prior dynamic), a monitor behind it (4:
// static), a low-confidence book (5: not classified); keypoints 0 and 5 removed.
std::string SemanticWriteTrace(const std::string& dir, const SemanticPlant& plant) {
  dynref::trace::RunHeader h;
  h.method = "semantic";
  h.config_json = SemanticConfig();
  const std::string path = dir + "/trace.dtr";
  dynref::trace::TraceWriter w(path, dynref::trace::Level::kFull, h);
  auto prob = [&](const std::string& stage, EntityKind kind, const std::string& id, Inputs in, double after) {
    if (stage == plant.stage && id == plant.entity) {
      after += plant.after_delta;
      for (size_t k = 0; k < in.size(); ++k)
        if (in[k].name == plant.drop_input) in.erase(in.begin() + static_cast<long>(k));
    }
    w.ProbabilityUpdate(stage, kind, id, in, 0.0, after);
  };
  auto decision = [&](EntityKind kind, const std::string& id, bool kept, std::string reason) {
    if (plant.stage == "semantic.mask.decision" && id == plant.entity) reason = plant.reason;
    w.Decision("semantic.mask", kind, id, kept, reason);
  };
  w.BeginFrame(2, 0.066);
  prob("semantic.interaction", EntityKind::kInstanceMask, "i2.3",
       {{"with_instance", 1}, {"pairs", 40}, {"dz_mean_m", 0.05}, {"t_int_m", 0.3}, {"d_max_px", 6}}, 1);
  prob("semantic.interaction", EntityKind::kInstanceMask, "i2.4",
       {{"with_instance", 1}, {"pairs", 10}, {"dz_mean_m", 0.8}, {"t_int_m", 0.3}, {"d_max_px", 6}}, 0);
  prob("semantic.mask", EntityKind::kInstanceMask, "i2.1", {{"class_id", 0}, {"confidence", 0.9}}, 1);
  decision(EntityKind::kInstanceMask, "i2.1", false, "prior-dynamic:person");
  prob("semantic.mask", EntityKind::kInstanceMask, "i2.3", {{"class_id", 56}, {"confidence", 0.8}}, 1);
  decision(EntityKind::kInstanceMask, "i2.3", false, "non-prior-dynamic:chair");
  prob("semantic.mask", EntityKind::kInstanceMask, "i2.4", {{"class_id", 62}, {"confidence", 0.7}}, 0);
  decision(EntityKind::kInstanceMask, "i2.4", true, "static:tvmonitor");
  prob("semantic.mask", EntityKind::kInstanceMask, "i2.5", {{"class_id", 73}, {"confidence", 0.1}}, 0);
  prob("semantic.mask", EntityKind::kFeature, "f2.0", {{"instance", 1}}, 1);
  decision(EntityKind::kFeature, "f2.0", false, "dynamic-mask");
  prob("semantic.mask", EntityKind::kFeature, "f2.5", {{"instance", 3}}, 1);
  decision(EntityKind::kFeature, "f2.5", false, "dynamic-mask");
  w.Close("complete");
  return path;
}

dynref::verify::VerifyReport SemanticVerify(const std::string& path) {
  return dynref::verify::test::VerifyWith(path, dynref::verify::AddSemanticVerifiers);
}

using dynref::verify::test::Examples;

}  // namespace

TEST_CASE("verify semantic: hand-built class partition, interaction and removal records verify", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_semantic_ok");
  const dynref::verify::VerifyReport r = SemanticVerify(SemanticWriteTrace(dir, {}));
  INFO(Examples(r));
  CHECK(r.ok());
  CHECK(r.stages.at("semantic.interaction").verified == 2);
  CHECK(r.stages.at("semantic.mask").verified == 11);
}

TEST_CASE("verify semantic: a planted wrong after or missing input is named", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_semantic_planted");
  struct Case { SemanticPlant plant; std::string stage; bool mismatch; std::string fragment; };
  const std::vector<Case> cases = {
      {{"semantic.interaction", "i2.4", "", 1.0, ""}, "semantic.interaction", true, "i2.4 field after"},
      {{"semantic.interaction", "i2.3", "dz_mean_m", 0, ""}, "semantic.interaction", false, "i2.3: not in the trace: input dz_mean_m"},
      {{"semantic.mask", "i2.5", "", 1.0, ""}, "semantic.mask", true, "i2.5 field after"},
      {{"semantic.mask", "i2.1", "class_id", 0, ""}, "semantic.mask", false, "prob semantic.mask i2.1: not in the trace: input class_id"},
      {{"semantic.mask", "f2.5", "instance", 0, ""}, "semantic.mask", false, "prob semantic.mask f2.5: not in the trace: input instance"},
      {{"semantic.mask.decision", "i2.4", "", 0, "static:chair"}, "semantic.mask", true, "i2.4 field reason"},
  };
  for (const Case& k : cases) {
    INFO(k.plant.stage + " " + k.plant.entity);
    const dynref::verify::VerifyReport r = SemanticVerify(SemanticWriteTrace(dir, k.plant));
    const std::string ex = Examples(r);
    INFO(ex);
    CHECK(!r.ok());
    const dynref::verify::StageReport& s = r.stages.at(k.stage);
    CHECK((k.mismatch ? s.mismatched : s.unverifiable) >= 1);
    CHECK(ex.find(k.fragment) != std::string::npos);
  }
}
