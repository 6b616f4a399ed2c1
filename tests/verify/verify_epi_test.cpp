// Tests of the epi verifiers (ref/verify/README.md "Enhanced-epipolar SLAM"): hand-built records of
// every epi stage and of the MNN2 matches recomputed, planted wrong records refused.
#include <catch2/catch.hpp>
#include <cmath>
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

struct EpiPlant {
  std::string stage, entity;
  std::string drop_input;
  double after_delta = 0;
  std::string input;  // an input to shift by input_delta
  double input_delta = 0;
};

nlohmann::json EpiParam(const nlohmann::json& v) { return {{"value", v}, {"source", "test"}}; }

constexpr double kEpiF = 500, kEpiCx = 320, kEpiCy = 240;

std::string EpiConfig() {
  nlohmann::json c;
  c["method"] = "epi_test";
  c["backbone"] = {{"mnn2_matching", EpiParam(true)}, {"mnn2_ratio", EpiParam(0.95)}};
  c["stages"] = nlohmann::json::array(
      {{{"name", "epi.enhance"},
        {"params",
         {{"s", EpiParam(0.01)}, {"optimise", EpiParam(false)}, {"alpha", EpiParam(0.5)}, {"p", EpiParam(1.0)},
          {"boa_population", EpiParam(20)}, {"boa_iterations", EpiParam(30)}, {"alpha_max", EpiParam(2.0)},
          {"p_min", EpiParam(0.25)}, {"p_max", EpiParam(3.0)}}}},
       {{"name", "epi.vote"},
        {"params", {{"epi_threshold_px", EpiParam(1.0)}, {"vote_ratio", EpiParam(0.6)}, {"pose_min_inliers", EpiParam(12)}}}},
       {{"name", "epi.nerf"},
        {"params", {{"parallax_cos_max", EpiParam(0.9998)}, {"reprojection_px", EpiParam(2.447651936)},
                    {"mnn_ratio", EpiParam(0.95)}}}}});
  return c.dump();
}

Inputs Pose(const std::string& prefix_r, double tx, double ty, double tz) {
  Inputs in;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) in.push_back({prefix_r + std::to_string(r) + std::to_string(k), r == k ? 1.0 : 0.0});
  in.push_back({"t0", tx});
  in.push_back({"t1", ty});
  in.push_back({"t2", tz});
  return in;
}

Inputs Mnn2(double kf, double i, double d1, double d2, double rev, double rev_d, double outcome) {
  return {{"kf", kf}, {"kf_feature", i}, {"map_point", 7}, {"distance", d1}, {"second", d2}, {"ratio", d1 / d2},
          {"tau", 100}, {"rho", 0.95}, {"second_feature", 9}, {"reverse_kf_feature", rev},
          {"reverse_distance", rev_d}, {"rotation_check", 0}, {"kf_angle", 0}, {"angle", 0}, {"outcome", outcome}};
}

// Frame 0: keyframe kf0 at the origin. Frame 1 (camera 0.1 m to the right, R = I): enhancement,
// the static-region pose t = (1, 0, 0) (epipolar lines horizontal: D = |v_prev - v_cur|), mask 1
// with three matched keypoints (D 0.5, 3, 6: 2 of 3 > 1 px, dynamic), mask 2 with an untracked
// keypoint (no match: dynamic), their exclusions; MNN2 rows (accepted, ratio, not mutual, one
// triangulation row the epipolar test rejects); the NeRF export of a match of X = (0.2, 0.1, 2).
std::string EpiWriteTrace(const std::string& dir, const EpiPlant& plant) {
  dynref::trace::RunHeader h;
  h.method = "epi_test";
  h.config_json = EpiConfig();
  h.extra.emplace_back("camera_json", nlohmann::json({{"fx", kEpiF}, {"fy", kEpiF}, {"cx", kEpiCx}, {"cy", kEpiCy}, {"bf", 40.0},
                                                      {"th_depth", 40.0}, {"width", 640}, {"height", 480},
                                                      {"k1", 0.0}, {"k2", 0.0}, {"p1", 0.0}, {"p2", 0.0}, {"k3", 0.0}})
                                          .dump());
  const std::string path = dir + "/trace.dtr";
  dynref::trace::TraceWriter w(path, dynref::trace::Level::kFull, h);
  auto prob = [&](const std::string& stage, EntityKind kind, const std::string& id, Inputs in, double after) {
    if (stage == plant.stage && id == plant.entity) {
      after += plant.after_delta;
      for (size_t k = 0; k < in.size(); ++k) {
        if (in[k].name == plant.input) in[k].value += plant.input_delta;
        if (in[k].name == plant.drop_input) in.erase(in.begin() + static_cast<long>(k--));
      }
    }
    w.ProbabilityUpdate(stage, kind, id, in, 0.0, after);
  };
  w.BeginFrame(0, 0.0);
  w.BeginFrame(1, 0.033);
  // Keypoints (OBS) of frame 1: u_cur / v_cur of the epipolar records.
  const double v_prev[4] = {100, 200, 204, 300}, v_cur[4] = {100.5, 203, 210, 300};
  for (int i = 0; i < 4; ++i) w.Observation(i, -1, 100.0 + 10 * i, v_cur[i], 0.0, 0, 0);
  const double sum = 5000, edges = 20000, pixels = 640 * 480, entropy = 7.1;
  prob("epi.enhance", EntityKind::kFrame, "f1",
       {{"I_lo", 3 / 255.0}, {"I_hi", 250 / 255.0}, {"cdf_lo_below", 0.004}, {"cdf_lo", 0.012},
        {"cdf_hi_below", 0.985}, {"cdf_hi", 0.995}, {"alpha", 0.5}, {"p", 1.0}, {"sobel_sum", sum},
        {"edge_pixels", edges}, {"pixels", pixels}, {"entropy", entropy},
        {"fitness", std::log(std::log(sum)) * (edges / pixels) * entropy}, {"mean_in", 0.2}, {"mean_out", 0.45}},
       0);
  Inputs pose = {{"static_pairs", 80}, {"inliers", 60}, {"min_inliers", 12}, {"pose", 1}};
  for (const NamedValue& v : Pose("R", 1, 0, 0)) pose.push_back(v);
  prob("epi.pose", EntityKind::kFrame, "f1", pose, 0);
  for (int i = 0; i < 4; ++i) {
    const bool tracked = i < 3;
    const double nan = std::nan(""), d = tracked ? std::abs(v_prev[i] - v_cur[i]) : nan;
    prob("epi.epipolar", EntityKind::kFeature, "f1." + std::to_string(i),
         {{"instance", tracked ? 1.0 : 2.0}, {"tracked", tracked ? 1.0 : 0.0}, {"pose", 1},
          {"u_prev", tracked ? 100.0 + 10 * i : nan}, {"v_prev", tracked ? v_prev[i] : nan},
          {"u_cur", tracked ? 100.0 + 10 * i : nan}, {"v_cur", tracked ? v_cur[i] : nan}, {"distance_px", d},
          {"eps_px", 1.0}},
         d > 1.0 ? 1.0 : 0.0);
  }
  prob("epi.vote", EntityKind::kInstanceMask, "i1.1",
       {{"matched", 3}, {"violating", 2}, {"ratio", 2.0 / 3.0}, {"vote_ratio", 0.6}}, 1);
  w.Decision("epi.vote", EntityKind::kInstanceMask, "i1.1", false, "vote>ratio");
  prob("epi.vote", EntityKind::kInstanceMask, "i1.2", {{"matched", 0}, {"violating", 0}, {"ratio", 0}, {"vote_ratio", 0.6}},
       1);
  w.Decision("epi.vote", EntityKind::kInstanceMask, "i1.2", false, "no-matched-keypoint");
  for (int i = 0; i < 4; ++i)
    w.Decision("epi.vote", EntityKind::kFeature, "f1." + std::to_string(i), false, "dynamic-mask");
  // MNN2 rows of one reference-keyframe call (kf 0) and one triangulation row.
  prob("match.mnn2.reference", EntityKind::kFeature, "f1.0", Mnn2(0, 5, 20, 60, 5, 20, 0), 0);
  prob("match.mnn2.reference", EntityKind::kFeature, "f1.1", Mnn2(0, 6, 40, 41, 6, 40, 2), 0);
  prob("match.mnn2.reference", EntityKind::kFeature, "f1.2", Mnn2(0, 8, 30, 70, 3, 25, 3), 0);
  Inputs tri = Mnn2(1, 4, 10, 50, 4, 10, 5);
  tri.insert(tri.begin() + 2, {"kf2", 0});
  tri.erase(tri.end() - 4, tri.end() - 1);  // no rotation check in the triangulation search
  for (const NamedValue& v : Inputs{{"epipole_d2", std::nan("")}, {"epipole_gate", std::nan("")}, {"line_d2", 9.0},
                                    {"line_gate", 3.84}})
    tri.insert(tri.end() - 1, v);
  prob("match.mnn2.triangulation", EntityKind::kFeature, "f0.11", tri, 0);
  // NeRF export: kf0 (frame 0, identity), kf1 (frame 1, T_cw translation (-0.1, 0, 0)).
  Inputs k0 = {{"frame", 0}, {"ref_kf", -1}}, k1 = {{"frame", 1}, {"ref_kf", 0}};
  for (const NamedValue& v : Pose("R", 0, 0, 0)) k0.push_back(v);
  for (const NamedValue& v : Pose("R", -0.1, 0, 0)) k1.push_back(v);
  prob("epi.nerf", EntityKind::kKeyFrame, "kf0", k0, 0);
  prob("epi.nerf", EntityKind::kKeyFrame, "kf1", k1, 0);
  const double X = 0.2, Y = 0.1, Z = 2;
  const double u1 = kEpiF * (X - 0.1) / Z + kEpiCx, v1 = kEpiF * Y / Z + kEpiCy, u0 = kEpiF * X / Z + kEpiCx;
  const double a[3] = {(u1 - kEpiCx) / kEpiF, (v1 - kEpiCy) / kEpiF, 1}, b[3] = {(u0 - kEpiCx) / kEpiF, (v1 - kEpiCy) / kEpiF, 1};
  const double cos = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) /
                     (std::sqrt(a[0] * a[0] + a[1] * a[1] + 1) * std::sqrt(b[0] * b[0] + b[1] * b[1] + 1));
  w.Observation(4, -1, u1, v1, 0.0, 0, 0);
  prob("epi.nerf", EntityKind::kFeature, "f1.4",
       {{"kf", 1}, {"ref_kf", 0}, {"ref_feature", 2}, {"distance", 20}, {"second", 60}, {"rho", 0.95}, {"tau", 100},
        {"u", u1}, {"v", v1}, {"ref_u", u0}, {"ref_v", v1}, {"cos_parallax", cos}, {"X", X}, {"Y", Y}, {"Z", Z},
        {"z", Z}, {"ref_z", Z}, {"err_px", 0}, {"ref_err_px", 0}, {"outcome", 0}},
       0);
  w.Close("complete");
  return path;
}

dynref::verify::VerifyReport EpiVerify(const std::string& path) {
  return dynref::verify::test::VerifyWith(path, dynref::verify::AddEpiVerifiers);
}

using dynref::verify::test::Examples;

}  // namespace

TEST_CASE("verify epi: the family registers its verifiers", "[verify]") {
  dynref::verify::VerifierList list;
  dynref::verify::AddEpiVerifiers(list);
  CHECK(!list.empty());
}

TEST_CASE("verify epi: hand-built enhancement, epipolar vote, MNN2 and NeRF records verify", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_epi_ok");
  const dynref::verify::VerifyReport r = EpiVerify(EpiWriteTrace(dir, {}));
  INFO(Examples(r));
  CHECK(r.ok());
  CHECK(r.stages.at("epi.enhance").verified == 1);
  CHECK(r.stages.at("epi.pose").verified == 1);
  CHECK(r.stages.at("epi.epipolar").verified == 4);
  CHECK(r.stages.at("epi.vote").verified == 8);  // 2 masks (PROB + DECISION), 4 exclusions
  CHECK(r.stages.at("match.mnn2.reference").verified == 3);
  CHECK(r.stages.at("match.mnn2.triangulation").verified == 1);
  CHECK(r.stages.at("epi.nerf").verified == 3);
}

TEST_CASE("verify epi: a planted wrong after, input or missing input is named", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_epi_planted");
  struct Case { EpiPlant plant; std::string stage; bool mismatch; std::string fragment; };
  const std::vector<Case> cases = {
      {{"epi.epipolar", "f1.0", "", 1.0}, "epi.epipolar", true, "f1.0 field after"},
      {{"epi.epipolar", "f1.1", "", 0, "distance_px", 0.25}, "epi.epipolar", true, "f1.1 field distance_px"},
      {{"epi.epipolar", "f1.2", "v_prev"}, "epi.epipolar", false, "f1.2: not in the trace: input v_prev"},
      {{"epi.vote", "i1.1", "", -1.0}, "epi.vote", true, "i1.1 field after"},
      {{"epi.enhance", "f1", "", 0, "fitness", 0.01}, "epi.enhance", true, "f1 field fitness"},
      {{"epi.enhance", "f1", "", 0, "cdf_lo_below", 0.01}, "epi.enhance", true, "f1 field I_lo"},
      {{"epi.pose", "f1", "", 0, "inliers", -50}, "epi.pose", true, "f1 field pose"},
      {{"match.mnn2.reference", "f1.1", "", 0, "outcome", -2}, "match.mnn2.reference", true, "f1.1 field outcome"},
      {{"match.mnn2.reference", "f1.0", "distance"}, "match.mnn2.reference", false, "input distance"},
      {{"match.mnn2.triangulation", "f0.11", "", 0, "line_d2", -8}, "match.mnn2.triangulation", true, "field outcome"},
      {{"epi.nerf", "f1.4", "", 0, "X", 0.01}, "epi.nerf", true, "f1.4 field X"},
      {{"epi.nerf", "kf1", "t0"}, "epi.nerf", false, "kf1: not in the trace: input t0"},
  };
  for (const Case& k : cases) {
    INFO(k.plant.stage + " " + k.plant.entity);
    const dynref::verify::VerifyReport r = EpiVerify(EpiWriteTrace(dir, k.plant));
    const std::string ex = Examples(r);
    INFO(ex);
    CHECK(!r.ok());
    const dynref::verify::StageReport& s = r.stages.at(k.stage);
    CHECK((k.mismatch ? s.mismatched : s.unverifiable) >= 1);
    CHECK(ex.find(k.fragment) != std::string::npos);
  }
}
