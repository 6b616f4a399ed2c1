// Tests of the sgdo verifiers (ref/verify/README.md): hand-built records recomputed, planted
// wrong records refused.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
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

// What a test plants in the otherwise consistent trace.
struct SgdoPlant {
  std::string stage, entity;  // the PROB to change
  std::string drop_input;     // remove this input
  double after_delta = 0;     // add this to `after`
  std::string reason;         // decision reason to write instead (decision of `entity`)
};

nlohmann::json SgdoParam(const nlohmann::json& v) { return {{"value", v}, {"source", "test"}}; }

std::string SgdoConfig() {
  nlohmann::json c;
  c["method"] = "sgdo";
  c["backbone"] = nlohmann::json::object();
  c["stages"] = nlohmann::json::array(
      {{{"name", "sgdo.mask"},
        {"params",
         {{"dynamic_classes", SgdoParam({"person"})}, {"min_confidence", SgdoParam("0.25")},
          {"dilation_kernel_px", SgdoParam("15")}, {"reject_in_mask", SgdoParam("false")}}}},
       {{"name", "sgdo.coarse"},
        {"params",
         {{"combination", SgdoParam("per_point")}, {"th_epi_px", SgdoParam("1.0")}, {"vote_ratio", SgdoParam("0.5")},
          {"border_px", SgdoParam("5")}, {"patch_sad_max", SgdoParam("2120")}, {"ransac_threshold_px", SgdoParam("1.0")}}}},
       {{"name", "sgdo.depth"},
        {"params", {{"eta", SgdoParam("0.1")}, {"lambda", SgdoParam("100")}, {"reject", SgdoParam("true")}, {"weight", SgdoParam("true")}}}}});
  return c.dump();
}

constexpr double kSgdoFx = 535.4, kSgdoFy = 539.2, kSgdoCx = 320.1, kSgdoCy = 247.6;

// One frame (1) of a consistent sgdo trace: two instances, ten LK pairs with F = [t]x for
// t = (1, 0, 0) (horizontal epipolar lines: D = |v_prev - v_cur|), and two depth tests.
std::string SgdoWriteTrace(const std::string& dir, const SgdoPlant& plant) {
  dynref::trace::RunHeader h;
  h.method = "sgdo";
  h.config_json = SgdoConfig();
  h.extra.push_back({"camera_json", nlohmann::json({{"fx", kSgdoFx}, {"fy", kSgdoFy}, {"cx", kSgdoCx}, {"cy", kSgdoCy}, {"bf", 40.0},
                                                    {"th_depth", 40.0}, {"width", 640}, {"height", 480}})
                                        .dump()});
  const std::string path = dir + "/trace.dtr";
  dynref::trace::TraceWriter w(path, dynref::trace::Level::kFull, h);
  auto prob = [&](const std::string& stage, EntityKind kind, const std::string& id, Inputs in, double before,
                  double after) {
    if (stage == plant.stage && id == plant.entity) {
      after += plant.after_delta;
      for (size_t k = 0; k < in.size(); ++k)
        if (in[k].name == plant.drop_input) in.erase(in.begin() + static_cast<long>(k));
    }
    w.ProbabilityUpdate(stage, kind, id, in, before, after);
  };
  auto decision = [&](const std::string& stage, EntityKind kind, const std::string& id, bool kept, std::string reason) {
    if (plant.stage == stage + ".decision" && id == plant.entity) reason = plant.reason;
    w.Decision(stage, kind, id, kept, reason);
  };
  w.BeginFrame(1, 0.033);
  // sgdo.mask: a person (in M) and a chair.
  prob("sgdo.mask", EntityKind::kInstanceMask, "i1.1", {{"class_id", 0}, {"confidence", 0.9}}, 0, 1);
  decision("sgdo.mask", EntityKind::kInstanceMask, "i1.1", false, "prior-dynamic:person");
  prob("sgdo.mask", EntityKind::kInstanceMask, "i1.2", {{"class_id", 56}, {"confidence", 0.8}}, 0, 0);
  decision("sgdo.mask", EntityKind::kInstanceMask, "i1.2", true, "static-class");
  // sgdo.coarse: features 0..7 usable (deltas 0.1 .. 0.7 and 3.0), 8 in M (tested), 9 LK failed in M.
  const double F[9] = {0, 0, 0, 0, 0, -1, 0, 1, 0};
  prob("sgdo.F", EntityKind::kFrame, "f1",
       {{"F00", F[0]}, {"F01", F[1]}, {"F02", F[2]}, {"F10", F[3]}, {"F11", F[4]}, {"F12", F[5]}, {"F20", F[6]},
        {"F21", F[7]}, {"F22", F[8]}, {"usable", 8}, {"inliers", 7}},
       0, 1);
  struct Pair { double u1, v1, u2, v2; int inst; bool tracked; };
  std::vector<Pair> pairs;
  for (int i = 0; i < 8; ++i) pairs.push_back({100.0 + 20 * i, 100, 102.0 + 20 * i, 100 + (i == 7 ? 3.0 : 0.1 * (i + 1)), 0, true});
  pairs.push_back({300, 300, 301, 300.5, 1, true});
  pairs.push_back({0, 0, 320, 320, 1, false});
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Pair& p = pairs[i];
    const std::string id = "f1." + std::to_string(i);
    const bool tested = p.tracked;
    const double D = tested ? std::abs(p.v1 - p.v2) : 0;
    const int prune = !p.tracked ? 1 : p.inst != 0 ? 4 : 0;
    const bool usable = p.tracked && prune == 0;
    prob("sgdo.epipolar", EntityKind::kFeature, id,
         {{"u_prev", p.u1}, {"v_prev", p.v1}, {"u_cur", p.u2}, {"v_cur", p.v2}, {"D_px", D}, {"th_epi_px", 1.0},
          {"instance", double(p.inst)}, {"used_for_F", usable ? 1.0 : 0.0}, {"F_inlier", usable && D <= 1 ? 1.0 : 0.0},
          {"patch_sad", p.tracked ? 50.0 : 0.0}, {"tracked", p.tracked ? 1.0 : 0.0}, {"F_valid", 1}, {"prune", double(prune)},
          {"tested", tested ? 1.0 : 0.0}},
         0, tested ? (D > 1 ? 1.0 : 0.0) : 0.5);
  }
  for (size_t i = 0; i < pairs.size(); ++i) {
    const std::string id = "f1." + std::to_string(i);
    if (i == 7) decision("sgdo.coarse", EntityKind::kFeature, id, false, "epipolar");
    else if (i == 9) decision("sgdo.coarse", EntityKind::kFeature, id, false, "mask-no-pair");
    else decision("sgdo.coarse", EntityKind::kFeature, id, true, "static");
  }
  // sgdo.depth: T_wc = I, T_kw = translation (0, 0, 0.1): z_k = d + 0.1.
  w.FramePose("initial", dynref::SE3::Identity());
  Inputs pose;
  const double T_kw[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.1};
  for (int k = 0; k < 12; ++k) pose.push_back({"T_kw[" + std::to_string(k) + "]", T_kw[k]});
  prob("sgdo.depth.kf", EntityKind::kKeyFrame, "kf0", pose, 0, 0);
  const double d_k[2] = {2.0, 1.5};  // feature 0: eps 0.05 (kept, omega e^-0.25); 1: eps 0.4 (rejected)
  for (int i = 0; i < 2; ++i) {
    const Pair& p = pairs[static_cast<size_t>(i)];
    const double d = 2.0, x = d * (p.u2 - kSgdoCx) / kSgdoFx, y = d * (p.v2 - kSgdoCy) / kSgdoFy, z = d + 0.1;
    const double eps = (z - d_k[i]) / d_k[i], omega = std::exp(-100 * eps * eps);
    const bool reject = std::abs(eps) > 0.1;
    prob("sgdo.depth", EntityKind::kFeature, "f1." + std::to_string(i),
         {{"kf", 0}, {"depth_i_m", d}, {"u_k", kSgdoFx * x / z + kSgdoCx}, {"v_k", kSgdoFy * y / z + kSgdoCy}, {"z_k", z}, {"d_k", d_k[i]},
          {"eps", eps}, {"eta", 0.1}, {"lambda", 100}, {"tested", 1}, {"omega", omega}, {"weight", reject ? 1.0 : omega}},
         0, reject ? 1.0 : 1.0 - omega);
    if (reject) decision("sgdo.depth", EntityKind::kFeature, "f1." + std::to_string(i), false, "depth-eps");
    else decision("sgdo.depth", EntityKind::kFeature, "f1." + std::to_string(i), true, "consistent");
  }
  w.FrameCount("sgdo.depth", "reference_kf", 0);
  for (size_t i = 0; i < pairs.size(); ++i)
    w.Observation(static_cast<int64_t>(i), -1, pairs[i].u2, pairs[i].v2, i < 2 ? 2.0 : 0.0, 0, 0);
  w.Close("complete");
  return path;
}

dynref::verify::VerifyReport SgdoVerify(const std::string& path) {
  return dynref::verify::test::VerifyWith(path, dynref::verify::AddSgdoVerifiers);
}

using dynref::verify::test::Examples;

}  // namespace

TEST_CASE("verify sgdo: hand-built records of every sgdo stage verify", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_sgdo_ok");
  const dynref::verify::VerifyReport r = SgdoVerify(SgdoWriteTrace(dir, {}));
  INFO(Examples(r));
  CHECK(r.ok());
  CHECK(r.stages.at("sgdo.epipolar").verified == 10);
  CHECK(r.stages.at("sgdo.coarse").verified == 10);
  CHECK(r.stages.at("sgdo.F").verified == 1);
  CHECK(r.stages.at("sgdo.mask").verified == 4);
  CHECK(r.stages.at("sgdo.depth").verified == 4);
  CHECK(r.stages.at("sgdo.depth.kf").verified == 1);
}

TEST_CASE("verify sgdo: a planted wrong after or missing input is named", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_sgdo_planted");
  struct Case { SgdoPlant plant; std::string stage; bool mismatch; std::string fragment; };
  const std::vector<Case> cases = {
      {{"sgdo.epipolar", "f1.3", "", 1.0, ""}, "sgdo.epipolar", true, "f1.3 field after"},
      {{"sgdo.epipolar", "f1.2", "D_px", 0, ""}, "sgdo.epipolar", false, "prob sgdo.epipolar f1.2: not in the trace: input D_px"},
      {{"sgdo.depth", "f1.0", "", 0.01, ""}, "sgdo.depth", true, "f1.0 field after"},
      {{"sgdo.depth", "f1.1", "d_k", 0, ""}, "sgdo.depth", false, "prob sgdo.depth f1.1: not in the trace: input d_k"},
      {{"sgdo.mask", "i1.2", "", 1.0, ""}, "sgdo.mask", true, "i1.2 field after"},
      {{"sgdo.mask", "i1.1", "confidence", 0, ""}, "sgdo.mask", false, "prob sgdo.mask i1.1: not in the trace: input confidence"},
      {{"sgdo.F", "f1", "", -1.0, ""}, "sgdo.F", true, "f1 field after"},
      {{"sgdo.coarse.decision", "f1.8", "", 0, "mask-no-pair"}, "sgdo.coarse", true, "f1.8 field reason"},
  };
  for (const Case& k : cases) {
    INFO(k.plant.stage + " " + k.plant.entity);
    const dynref::verify::VerifyReport r = SgdoVerify(SgdoWriteTrace(dir, k.plant));
    const std::string ex = Examples(r);
    INFO(ex);
    CHECK(!r.ok());
    const dynref::verify::StageReport& s = r.stages.at(k.stage);
    CHECK((k.mismatch ? s.mismatched : s.unverifiable) >= 1);
    CHECK(ex.find(k.fragment) != std::string::npos);
  }
}
