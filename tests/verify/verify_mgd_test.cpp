// Tests of the mgd verifiers (ref/verify/README.md, "MGD-SLAM"): a hand-built two-frame trace
// (initialisation frame 0, tracked frame 1 with three features and one line) whose records are
// computed here from the paper's equations is verified record by record; planted wrong records
// (an `after` changed, an input removed, a wrong decision) are refused, naming the record.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "test_support.h"
#include "trace/trace_reader.h"
#include "trace/trace_writer.h"
#include "verify/verifier.h"
#include "verify/verify_run.h"
#include "verify_test_support.h"

namespace {

using dynref::verify::test::Examples;

using dynref::trace::EntityKind;
using dynref::trace::NamedValue;
using Inputs = std::vector<NamedValue>;

struct MgdPlant {
  std::string stage, entity;  // the PROB (or DECISION, stage "<stage>.decision") to change
  std::string drop_input;
  double after_delta = 0;
  bool flip_kept = false;
};

nlohmann::json MgdParam(const nlohmann::json& v) { return {{"value", v}, {"source", "test"}}; }

std::string MgdConfig() {
  nlohmann::json p = {{"min_confidence", MgdParam(0.5)}, {"initial_pose_out_of_box", MgdParam(true)},
                      {"p_init_box", MgdParam(0.5)}, {"p_init_free", MgdParam(0.0)}, {"delta", MgdParam(0.6)},
                      {"match_radius_px", MgdParam(15)}, {"use_ls", MgdParam(true)}, {"use_pro", MgdParam(true)},
                      {"use_mf", MgdParam(true)}, {"d_th_ls_px", MgdParam(3)}, {"theta_th_ls_rad", MgdParam(2)},
                      {"a_ls", MgdParam(0.5)}, {"angle_form", MgdParam("angle_to_mean")}, {"min_velocity_px", MgdParam(0.5)},
                      {"d_th_pro_px", MgdParam(2)}, {"a_pro", MgdParam(1.0)}, {"d_th_mf_px", MgdParam(2)}, {"a_mf", MgdParam(1.0)},
                      {"w_ls", MgdParam(0.4)}, {"w_pro", MgdParam(0.4)}, {"w_mf", MgdParam(0.2)}, {"a", MgdParam(0.7)},
                      {"smoothing", MgdParam("new_evidence")}, {"diffusion", MgdParam(true)}, {"radius_m", MgdParam(0.15)},
                      {"line_cue_form", MgdParam("pseudo_point")}, {"tau_dyn", MgdParam(0.5)}, {"weight", MgdParam("one_minus_p")}};
  nlohmann::json c;
  c["method"] = "mgd";
  c["backbone"] = {{"features", MgdParam("orb")}};
  c["stages"] = nlohmann::json::array({{{"name", "mgd.boxes"}}, {{"name", "mgd.probability"}, {"params", p}},
                                       {{"name", "mgd.reprojection"}}});
  return c.dump();
}

constexpr double kMgdFx = 535.4, kMgdFy = 539.2, kMgdCx = 320.1, kMgdCy = 247.6;
double Sig(double z) { return 1.0 / (1.0 + std::exp(-z)); }
double Logit(double p) { return std::log(p / (1.0 - p)); }

// Frame 0: three features (1 and 2 in a box) and one line, P_init; the map point mp5 of feature
// 2 gets P_pro = sig((1 + 3) / 2 - 2) = 0.5 from keyframe 0. Frame 1: camera moved by t = 0.1 m
// along x (horizontal epipolar lines: d_epi = |v - v_prev|), every feature corresponds to its
// index in frame 0, all three within 0.15 m of each other (diffusion), feature 2 on mp5.
std::string MgdWriteTrace(const std::string& dir, const MgdPlant& plant) {
  dynref::trace::RunHeader h;
  h.method = "mgd";
  h.config_json = MgdConfig();
  h.extra.push_back({"camera_json", nlohmann::json({{"fx", kMgdFx}, {"fy", kMgdFy}, {"cx", kMgdCx}, {"cy", kMgdCy}, {"bf", 40.0},
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
  auto decision = [&](const std::string& stage, EntityKind kind, const std::string& id, bool kept,
                      const std::string& reason) {
    if (plant.stage == stage + ".decision" && id == plant.entity && plant.flip_kept) kept = !kept;
    w.Decision(stage, kind, id, kept, reason);
  };
  const double in_box[3] = {0, 1, 1};
  const double u0[3] = {100, 110, 105}, v0[3] = {200, 205, 210};
  const double u1[3] = {102.5, 118, 107}, v1[3] = {200.5, 214, 210.25}, z1[3] = {2.0, 2.05, 2.1};
  // ---- frame 0 (initialisation) ----
  w.BeginFrame(0, 0.0);
  double p0[3];
  for (int i = 0; i < 3; ++i) {
    p0[i] = in_box[i] != 0 ? 0.5 : 0.0;
    prob("mgd.boxes", EntityKind::kFeature, "f0." + std::to_string(i), {{"in_box", in_box[i]}, {"weight", 1.0 - p0[i]}},
         p0[i], p0[i]);
  }
  const double line_box[3] = {0, 0, 1};
  for (int k = 0; k < 3; ++k)
    prob("mgd.boxes", EntityKind::kLineSample, "l0.0", {{"sample", double(k)}, {"in_box", line_box[k]}}, 0.5 * line_box[k],
         0.5 * line_box[k]);
  prob("mgd.boxes", EntityKind::kLineSample, "l0.0", {{"weight", 0.5}}, 0.5, 0.5);
  w.FramePose("initial", dynref::SE3::Identity());
  w.FramePose("final", dynref::SE3::Identity());
  for (int i = 0; i < 3; ++i) w.Observation(i, i == 2 ? 5 : -1, u0[i], v0[i], 2.0, 0, 0);
  prob("structure", EntityKind::kLineSample, "l0.0", {{"x0", 300}, {"y0", 100}, {"x1", 300}, {"y1", 200}}, 0, 0);
  prob("mgd.reprojection", EntityKind::kMapPoint, "mp5",
       {{"kf", 0}, {"covisible", 2}, {"with_depth", 1}, {"mean_forward_px", 1.0}, {"mean_backward_px", 3.0}}, 0.5, 0.5);
  // ---- frame 1 ----
  w.BeginFrame(1, 0.033);
  dynref::SE3 T_wc = dynref::SE3::Identity();
  T_wc.translation() = Eigen::Vector3d(0.1, 0, 0);
  w.FramePose("initial", T_wc);
  // vbar: the out-of-box corresponded feature (0): v = (2.5, 0.5).
  const double vbar_u = 2.5, vbar_v = 0.5;
  Inputs frame_in = {{"prev_frame", 0}, {"n_vbar", 1}, {"vbar_u", vbar_u}, {"vbar_v", vbar_v}, {"has_T", 1}, {"has_F", 1}};
  const double I[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  for (int k = 0; k < 12; ++k) frame_in.push_back({"prev_T_cw[" + std::to_string(k) + "]", I[k]});
  prob("mgd.frame", EntityKind::kFrame, "f1", frame_in, 0, 0);
  double p_smooth[3];
  for (int i = 0; i < 3; ++i) {
    const std::string id = "f1." + std::to_string(i);
    const double mp = i == 2 ? 5 : -1;
    prob("mgd.inherit", EntityKind::kFeature, id,
         {{"source", 0}, {"prev_index", double(i)}, {"map_point", mp}, {"in_box", in_box[i]}, {"hamming", 20}}, p0[i],
         p0[i]);
    const double vu = u1[i] - u0[i], vv = v1[i] - v0[i];
    const double du = vu - vbar_u, dv = vv - vbar_v, d = std::sqrt(du * du + dv * dv);
    const double nv = std::sqrt(vu * vu + vv * vv), nb = std::sqrt(vbar_u * vbar_u + vbar_v * vbar_v);
    const double dtheta = std::acos(std::min(1.0, std::max(-1.0, (vu * vbar_u + vv * vbar_v) / (nv * nb))));
    const double p_ls = Sig(0.5 * (d - 3) + 0.5 * (dtheta - 2));
    prob("mgd.P_LS", EntityKind::kFeature, id,
         {{"computable", 1}, {"d_px", d}, {"dtheta", dtheta}, {"vbar_u", vbar_u}, {"vbar_v", vbar_v}}, 0.5, p_ls);
    const double p_pro = i == 2 ? Sig(0.5 * (1.0 + 3.0) - 2) : 0.5;
    prob("mgd.P_pro", EntityKind::kFeature, id,
         {{"computable", i == 2 ? 1.0 : 0.0}, {"mean_forward_px", i == 2 ? 1.0 : 0.0},
          {"mean_backward_px", i == 2 ? 3.0 : 0.0}, {"covisible", i == 2 ? 2.0 : 0.0}, {"kf", i == 2 ? 0.0 : -1.0},
          {"source_mp", i == 2 ? 5.0 : -1.0}},
         0.5, p_pro);
    const double d_epi = std::fabs(v1[i] - v0[i]), p_mf = Sig(d_epi - 2);
    prob("mgd.P_mf", EntityKind::kFeature, id, {{"computable", 1}, {"d_epi_px", d_epi}}, 0.5, p_mf);
    const double S = Sig(0.4 * Logit(p_ls) + 0.4 * Logit(p_pro) + 0.2 * Logit(p_mf));
    prob("mgd.fusion", EntityKind::kFeature, id, {{"w_ls", 0.4}, {"w_pro", 0.4}, {"w_mf", 0.2}}, 0.5, S);
    p_smooth[i] = 0.3 * p0[i] + 0.7 * S;
    prob("mgd.smooth", EntityKind::kFeature, id, {{"S", S}, {"a", 0.7}}, p0[i], p_smooth[i]);
  }
  // Line 0 (no correspondence: P_init of its samples, cues not computable; no depth).
  for (int k = 0; k < 3; ++k) {
    const double s = k, p = 0.5 * line_box[k];
    prob("mgd.inherit", EntityKind::kLineSample, "l1.0",
         {{"sample", s}, {"source", 2}, {"prev_index", -1}, {"prev_sample", s}, {"map_line", -1}, {"in_box", line_box[k]},
          {"hamming", -1}, {"match", 0}},
         p, p);
    prob("mgd.P_LS", EntityKind::kLineSample, "l1.0",
         {{"sample", s}, {"computable", 0}, {"d_px", 0}, {"dtheta", 0}, {"map_line", -1}, {"vbar_u", vbar_u}, {"vbar_v", vbar_v}},
         0.5, 0.5);
    prob("mgd.P_pro", EntityKind::kLineSample, "l1.0", {{"sample", s}, {"computable", 0}}, 0.5, 0.5);
    prob("mgd.P_mf", EntityKind::kLineSample, "l1.0", {{"sample", s}, {"computable", 0}, {"d_px", 0}, {"map_line", -1}}, 0.5, 0.5);
    prob("mgd.fusion", EntityKind::kLineSample, "l1.0", {{"sample", s}, {"w_ls", 0.4}, {"w_pro", 0.4}, {"w_mf", 0.2}}, 0.5, 0.5);
    prob("mgd.smooth", EntityKind::kLineSample, "l1.0", {{"sample", s}, {"S", 0.5}, {"a", 0.7}, {"map_line", -1}}, p,
         0.3 * (0.5 * line_box[k]) + 0.7 * 0.5);
  }
  // Diffusion (Jacobi) over the three feature points.
  Eigen::Vector3d X[3];
  for (int i = 0; i < 3; ++i) X[i] = Eigen::Vector3d((u1[i] - kMgdCx) * z1[i] / kMgdFx, (v1[i] - kMgdCy) * z1[i] / kMgdFy, z1[i]);
  double p[3];
  for (int i = 0; i < 3; ++i) {
    double sw = 0, swp = 0;
    for (int j = 0; j < 3; ++j) {
      if (j == i) continue;
      const double dd = (X[i] - X[j]).norm();
      REQUIRE(dd <= 0.15);
      sw += std::exp(-dd / 0.15), swp += std::exp(-dd / 0.15) * (p_smooth[j] - p_smooth[i]);
    }
    p[i] = p_smooth[i] + swp / (1 + sw);
  }
  for (int i = 0; i < 3; ++i) {
    const bool kept = p[i] <= 0.5;
    prob("mgd.diffuse", EntityKind::kFeature, "f1." + std::to_string(i),
         {{"neighbours", 2}, {"weight", kept ? 1 - p[i] : 0}, {"has_point", 1}, {"x", X[i].x()}, {"y", X[i].y()},
          {"z", X[i].z()}},
         p_smooth[i], p[i]);
    if (i == 2) prob("mgd.map_point", EntityKind::kMapPoint, "mp5", {{"feature", 2}, {"had_p", 0}}, p[i], p[i]);
    decision("mgd.probability", EntityKind::kFeature, "f1." + std::to_string(i), kept, kept ? "p<=tau_dyn" : "p>tau_dyn");
  }
  double line_before = 0, line_p = 0;
  for (int k = 0; k < 3; ++k) {
    const double ps = 0.3 * (0.5 * line_box[k]) + 0.7 * 0.5;  // as the smooth record
    line_before = std::max(line_before, ps), line_p = std::max(line_p, ps);
    prob("mgd.diffuse", EntityKind::kLineSample, "l1.0",
         {{"sample", double(k)}, {"neighbours", 0}, {"map_line", -1}, {"has_point", 0}, {"x", 0}, {"y", 0}, {"z", 0}}, ps, ps);
  }
  const double lw = line_p > 0.5 ? 0 : 1 - line_p;
  prob("mgd.line", EntityKind::kLineSample, "l1.0", {{"map_line", -1}, {"weight", lw}}, line_before, line_p);
  decision("mgd.probability", EntityKind::kLineSample, "l1.0", lw > 0, lw > 0 ? "max_p<=tau_dyn" : "max_p>tau_dyn");
  for (int i = 0; i < 3; ++i) w.Observation(i, i == 2 ? 5 : -1, u1[i], v1[i], z1[i], 0, 0);
  // ---- frame 2: tracking was lost; the in-box feature 1 keeps its box prior 1 - 0.5 ----
  w.BeginFrame(2, 0.066);
  prob("mgd.boxes", EntityKind::kFeature, "f2.1", {{"lost", 1}, {"in_box", 1}, {"weight", 0.5}}, 0, 0);
  w.Close("complete");
  return path;
}

dynref::verify::VerifyReport MgdVerify(const std::string& path) {
  dynref::trace::TraceReader reader(path);
  const dynref::verify::TraceModel model(reader);
  dynref::verify::VerifierList list;
  dynref::verify::AddMgdVerifiers(list);
  // The structure records are the backbone's: claimed here by a stub so the report is the mgd one.
  struct Structure : dynref::verify::Verifier {
    bool Claims(const dynref::trace::Record& r) const override { return r.stage == "structure"; }
    void Verify(const dynref::verify::TraceModel&, dynref::verify::RecordRef, dynref::verify::Check&) const override {}
  };
  list.push_back(std::make_unique<Structure>());
  return dynref::verify::VerifyTrace(model, list, {});
}

}  // namespace

TEST_CASE("verify mgd: a consistent hand-built trace verifies record by record", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_mgd_ok");
  const auto report = MgdVerify(MgdWriteTrace(dir, {}));
  INFO(Examples(report));
  CHECK(report.mismatched == 0);
  CHECK(report.unverifiable == 0);
  for (const char* stage : {"mgd.boxes", "mgd.frame", "mgd.inherit", "mgd.P_LS", "mgd.P_pro", "mgd.P_mf", "mgd.fusion",
                            "mgd.smooth", "mgd.diffuse", "mgd.map_point", "mgd.line", "mgd.reprojection",
                            "mgd.probability"}) {
    INFO(stage);
    REQUIRE(report.stages.count(stage) == 1);
    CHECK(report.stages.at(stage).verified > 0);
  }
}

TEST_CASE("verify mgd: a changed `after` is a mismatch naming the record", "[verify]") {
  struct Case {
    const char* stage;
    const char* entity;
    const char* frame;
  };
  for (const Case& k : {Case{"mgd.diffuse", "f1.1", "1"}, Case{"mgd.P_mf", "f1.0", "1"}, Case{"mgd.P_LS", "f1.2", "1"},
                        Case{"mgd.smooth", "l1.0", "1"}, Case{"mgd.boxes", "f0.1", "0"}, Case{"mgd.boxes", "f2.1", "2"}, Case{"mgd.inherit", "f1.0", "1"},
                        Case{"mgd.reprojection", "mp5", "0"}, Case{"mgd.map_point", "mp5", "1"}}) {
    MgdPlant p;
    p.stage = k.stage, p.entity = k.entity, p.after_delta = 0.01;
    const auto report = MgdVerify(MgdWriteTrace(dynref::test::ScratchDir("verify_mgd_after"), p));
    INFO(k.stage << " " << k.entity << "\n" << Examples(report));
    REQUIRE(report.stages.count(k.stage) == 1);
    CHECK(report.stages.at(k.stage).mismatched >= 1);
    CHECK(Examples(report).find(std::string("mismatch frame ") + k.frame + " prob " + k.stage + " " + k.entity) !=
          std::string::npos);
  }
}

TEST_CASE("verify mgd: a removed input makes the record unverifiable", "[verify]") {
  struct Case {
    const char* stage;
    const char* entity;
    const char* input;
  };
  for (const Case& k : {Case{"mgd.diffuse", "f1.0", "x"}, Case{"mgd.frame", "f1", "prev_T_cw[3]"},
                        Case{"mgd.P_pro", "f1.2", "source_mp"}, Case{"mgd.inherit", "l1.0", "prev_sample"}}) {
    MgdPlant p;
    p.stage = k.stage, p.entity = k.entity, p.drop_input = k.input;
    const auto report = MgdVerify(MgdWriteTrace(dynref::test::ScratchDir("verify_mgd_drop"), p));
    INFO(k.stage << " " << k.input << "\n" << Examples(report));
    REQUIRE(report.stages.count(k.stage) == 1);
    CHECK(report.stages.at(k.stage).unverifiable >= 1);
    CHECK(Examples(report).find(std::string("unverifiable frame 1 prob ") + k.stage + " " + k.entity) != std::string::npos);
    CHECK(Examples(report).find(k.input) != std::string::npos);
  }
}

TEST_CASE("verify mgd: a lost frame's box-prior weight must be 1 - p_init_box", "[verify]") {
  MgdPlant p;
  p.stage = "mgd.boxes", p.entity = "f2.1", p.drop_input = "weight";
  const auto report = MgdVerify(MgdWriteTrace(dynref::test::ScratchDir("verify_mgd_lost"), p));
  INFO(Examples(report));
  CHECK(report.stages.at("mgd.boxes").unverifiable == 1);
  CHECK(Examples(report).find("unverifiable frame 2 prob mgd.boxes f2.1") != std::string::npos);
}

TEST_CASE("verify mgd: a decision against tau_dyn is a mismatch", "[verify]") {
  MgdPlant p;
  p.stage = "mgd.probability.decision", p.entity = "f1.1", p.flip_kept = true;
  const auto report = MgdVerify(MgdWriteTrace(dynref::test::ScratchDir("verify_mgd_decision"), p));
  INFO(Examples(report));
  REQUIRE(report.stages.count("mgd.probability") == 1);
  CHECK(report.stages.at("mgd.probability").mismatched == 1);
  CHECK(Examples(report).find("mgd.probability f1.1 field kept") != std::string::npos);
}
