// Tests of the backbone verifiers (ref/verify/README.md "Backbone"): a hand-built trace of
// pose-only and local-BA residuals (points, a line, a plane) with their link, keyframe and
// structure records is recomputed; planted wrong records (chi2, weight, inlier, end residual,
// a link's p, a missing link or link input) are refused naming the record.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"
#include "trace/trace_reader.h"
#include "trace/trace_writer.h"
#include "verify/verifier.h"
#include "verify/verify_run.h"

namespace {

using dynref::trace::EntityKind;
using dynref::trace::NamedValue;
using Inputs = std::vector<NamedValue>;

nlohmann::json BackboneParam(const nlohmann::json& v) { return {{"value", v}, {"source", "test"}}; }

std::string BackboneConfig() {
  nlohmann::json c;
  c["method"] = "orb";
  c["backbone"] = {{"features", BackboneParam("orb")},           {"scale_factor", BackboneParam("1.2")},
                   {"n_levels", BackboneParam("8")},             {"pose_chi2_mono", BackboneParam("5.991")},
                   {"pose_chi2_stereo", BackboneParam("7.815")}, {"pose_weighted_outlier_test", BackboneParam("false")},
                   {"ba_chi2_mono", BackboneParam("5.991")},     {"ba_chi2_stereo", BackboneParam("7.815")},
                   {"ba_weighted_outlier_test", BackboneParam("false")}, {"line_literal_residual", BackboneParam("false")},
                   {"line_sigma_px", BackboneParam("1")},        {"plane_angle_sigma_deg", BackboneParam("1")},
                   {"plane_dist_sigma_m", BackboneParam("0.02")}};
  c["stages"] = nlohmann::json::array();
  return c.dump();
}

// What a test plants in the otherwise consistent trace.
enum class Plant { kNone, kChi2, kWeight, kInlier, kEnd, kLinkAfter, kNoLink, kNoLinkFeature, kNoKeyFrame, kMapLine };

double Huber(double s, double d2) { return s <= d2 ? s : 2 * std::sqrt(s * d2) - d2; }

// Frame 1: T_wc = I before and after the one pose-only call; camera fx = fy = 500, (320, 240),
// bf = 40. Feature 0 (octave 1, depth 2 m, weight 0.5 from a method PROB) observes mp5 at
// (0.04, 0.04, 2) with a (1, 0, 1) px residual; feature 1 (octave 0, no depth) observes mp6 with
// a (0, 3) residual: chi2 9 > 5.991, outlier. Line ml3 (frame line 0) and plane mpl2 (frame plane
// 0) join the call; keyframe kf1 is made and local BA #1 observes mp5 in it.
std::string BackboneWriteTrace(const std::string& dir, Plant plant) {
  dynref::trace::RunHeader h;
  h.method = "orb";
  h.config_json = BackboneConfig();
  h.extra.push_back({"camera_json", nlohmann::json({{"fx", 500.0}, {"fy", 500.0}, {"cx", 320.0}, {"cy", 240.0},
                                                    {"bf", 40.0}, {"th_depth", 40.0}, {"width", 640}, {"height", 480}})
                                        .dump()});
  const std::string path = dir + "/trace.dtr";
  dynref::trace::TraceWriter w(path, dynref::trace::Level::kFull, h);
  w.BeginFrame(0, 0.0);
  w.ProbabilityUpdate("track.keyframe", EntityKind::kKeyFrame, "kf0", {{"frame", 0}}, 0, 0);
  w.BeginFrame(1, 0.033);
  w.ProbabilityUpdate("mgd.diffuse", EntityKind::kFeature, "f1.0", {{"neighbours", 3}, {"weight", 0.5}}, 0.4, 0.5);
  w.FramePose("initial", dynref::SE3::Identity());
  const double info0 = 1 / (1.2 * 1.2);  // octave 1: sigma = 1.2
  const std::vector<double> e0 = {1, 0, 1}, e1 = {0, 3};
  // Point 0 (rgbd3, inlier).
  {
    const double sq = 2, chi2 = info0 * sq;
    if (plant != Plant::kNoLink) {
      Inputs in = {{"feature", 0}, {"x", 0.04}, {"y", 0.04}, {"z", 2.0}};
      if (plant == Plant::kNoLinkFeature) in.erase(in.begin());
      w.ProbabilityUpdate("track.pose.obs", EntityKind::kFeature, "mp5@f1", in, 0, plant == Plant::kLinkAfter ? 0.5 : 0);
    }
    std::vector<double> end = e0;
    if (plant == Plant::kEnd) end[0] += 1e-3;
    const double sq_end = end[0] * end[0] + end[1] * end[1] + end[2] * end[2];
    w.Residual("track.pose#1", "rgbd3", "mp5@f1", e0, end, info0, plant == Plant::kWeight ? 1.0 : 0.5,
               Huber(info0 * 0.5 * sq_end, 7.815), plant == Plant::kChi2 ? chi2 + 0.1 : info0 * sq_end,
               plant != Plant::kInlier);
  }
  // Point 1 (mono2, outlier).
  w.ProbabilityUpdate("track.pose.obs", EntityKind::kFeature, "mp6@f1", {{"feature", 1}, {"x", -0.08}, {"y", -0.16}, {"z", 2.0}}, 0, 0);
  w.Residual("track.pose#1", "mono2", "mp6@f1", e1, e1, 1.0, 1.0, Huber(9, 5.991), 9, false);
  // Line (line4: sigma 1 px) and plane (sigma_a 1 deg, sigma_d 0.02 m).
  const std::vector<double> el = {0.5, -0.5, 0.2, 0.1}, ep = {0.01, 0.0, 0.02};
  w.ProbabilityUpdate("track.pose.obs", EntityKind::kLineSample, "ml3@f1", {{"line", 0}}, 0, 0);
  w.Residual("track.pose#1", "line4", "ml3@f1", el, el, 1.0, 1.0, 0.55, 0.55, true);
  const double sa = M_PI / 180, chi2p = ep[0] * ep[0] / (sa * sa) + ep[2] * ep[2] / (0.02 * 0.02);
  w.ProbabilityUpdate("track.pose.obs", EntityKind::kPlane, "mpl2@f1", {{"plane", 0}}, 0, 0);
  w.Residual("track.pose#1", "plane3", "mpl2@f1", ep, ep, 1 / (0.02 * 0.02), 1.0, chi2p, chi2p, true);
  w.FramePose("final", dynref::SE3::Identity());
  // u_r = u - bf / depth = 331 - 20 (feature 0); feature 1 has no depth.
  w.Observation(0, 5, 331, 250, 2.0, 1, 0x1234);
  w.Observation(1, -1, 300, 203, 0.0, 0, 0x5678);
  w.ProbabilityUpdate(dynref::trace::kGeometryStage, EntityKind::kLineSample, "l1.0",
                      {{"x0", 10}, {"y0", 10}, {"x1", 100}, {"y1", 12}, {"map_line", plant == Plant::kMapLine ? 4 : 3},
                       {"has_3d", 1}, {"group", 0}},
                      0, 0);
  w.ProbabilityUpdate(dynref::trace::kGeometryStage, EntityKind::kPlane, "pl1.0",
                      {{"x_min", 0}, {"y_min", 0}, {"x_max", 50}, {"y_max", 60}, {"n_x", 0}, {"n_y", 0.6}, {"n_z", -0.8},
                       {"d", 2.5}, {"points", 900}, {"map_plane", 2}},
                      0, 0);
  if (plant != Plant::kNoKeyFrame)
    w.ProbabilityUpdate("track.keyframe", EntityKind::kKeyFrame, "kf1", {{"frame", 1}}, 0, 0);
  // Local BA: mp5 in kf1 (feature 0 of frame 1), kept through the robust phase.
  w.ProbabilityUpdate("localba.obs", EntityKind::kFeature, "mp5@kf1", {{"feature", 0}, {"robust_chi2", 1.5}}, 0, 0);
  w.Residual("localba#1", "rgbd3", "mp5@kf1", e0, e0, info0, 0.5, Huber(info0 * 0.5 * 2, 7.815), info0 * 2, true);
  // The same observation dropped after the robust phase (robust chi2 9 > 7.815): an outlier.
  w.ProbabilityUpdate("localba.obs", EntityKind::kFeature, "mp5@kf1", {{"feature", 0}, {"robust_chi2", 9.0}}, 0, 0);
  w.Residual("localba#2", "rgbd3", "mp5@kf1", e0, e0, info0, 0.5, Huber(info0 * 0.5 * 2, 7.815), info0 * 2, false);
  w.Close("complete");
  return path;
}

dynref::verify::VerifyReport BackboneVerify(Plant plant, const std::string& name, std::string* text = nullptr) {
  const std::string dir = dynref::test::ScratchDir("verify_backbone_" + name);
  const std::string path = BackboneWriteTrace(dir, plant);
  dynref::trace::TraceReader reader(path);
  const dynref::verify::TraceModel model(reader);
  dynref::verify::VerifierList list;
  dynref::verify::AddBackboneVerifiers(list);
  const dynref::verify::VerifyReport report = dynref::verify::VerifyTrace(model, list, {});
  std::ostringstream out;
  dynref::verify::WriteVerifyReport(report, model, out);
  if (text != nullptr) *text = out.str();
  return report;
}

}  // namespace

TEST_CASE("verify backbone: the family registers its verifiers", "[verify]") {
  dynref::verify::VerifierList list;
  dynref::verify::AddBackboneVerifiers(list);
  CHECK(!list.empty());
}

TEST_CASE("verify backbone: hand-built residual, link, keyframe and structure records verify", "[verify]") {
  std::string text;
  const auto r = BackboneVerify(Plant::kNone, "ok", &text);
  INFO(text);
  // 4 pose-only residuals + 4 links, 2 BA residuals + 2 links, 2 keyframes, 2 structure, and the
  // mgd.diffuse record (not a backbone stage: unverifiable here).
  CHECK(r.stages.at("track.pose").verified == 4);
  CHECK(r.stages.at("track.pose.obs").verified == 4);
  CHECK(r.stages.at("localba").verified == 2);
  CHECK(r.stages.at("localba.obs").verified == 2);
  CHECK(r.stages.at("track.keyframe").verified == 2);
  CHECK(r.stages.at("structure").verified == 2);
  CHECK(r.mismatched == 0);
  CHECK(r.unverifiable == 1);
  CHECK(r.stages.at("mgd.diffuse").unverifiable == 1);
}

TEST_CASE("verify backbone: planted wrong residual fields are mismatches naming the record", "[verify]") {
  struct Case {
    Plant plant;
    std::string name, stage, field;
  };
  const std::vector<Case> cases = {
      {Plant::kChi2, "chi2", "track.pose", "field chi2"},
      {Plant::kWeight, "weight", "track.pose", "field weight"},
      {Plant::kInlier, "inlier", "track.pose", "field inlier"},
      {Plant::kEnd, "end", "track.pose", "field end[0]"},
      {Plant::kLinkAfter, "link_after", "track.pose.obs", "field after"},
      {Plant::kMapLine, "map_line", "structure", "field map_line"},
  };
  for (const Case& c : cases) {
    std::string text;
    const auto r = BackboneVerify(c.plant, c.name, &text);
    INFO(c.name << "\n" << text);
    CHECK(r.stages.at(c.stage).mismatched == 1);
    CHECK(r.mismatched == 1);
    CHECK(text.find("mismatch frame 1") != std::string::npos);
    CHECK(text.find(c.field) != std::string::npos);
  }
}

TEST_CASE("verify backbone: a missing link, link input or keyframe record makes residuals unverifiable", "[verify]") {
  {
    std::string text;
    const auto r = BackboneVerify(Plant::kNoLink, "no_link", &text);
    INFO(text);
    CHECK(r.stages.at("track.pose").unverifiable == 1);
    CHECK(text.find("unverifiable frame 1 residual track.pose#1 mp5@f1") != std::string::npos);
    CHECK(text.find("link record track.pose.obs mp5@f1") != std::string::npos);
  }
  {
    std::string text;
    const auto r = BackboneVerify(Plant::kNoLinkFeature, "no_link_feature", &text);
    INFO(text);
    CHECK(r.stages.at("track.pose").unverifiable == 1);
    CHECK(r.stages.at("track.pose.obs").unverifiable == 1);
    CHECK(text.find("input feature") != std::string::npos);
  }
  {
    std::string text;
    const auto r = BackboneVerify(Plant::kNoKeyFrame, "no_keyframe", &text);
    INFO(text);
    CHECK(r.stages.at("localba").unverifiable == 2);
    CHECK(r.stages.at("localba.obs").unverifiable == 2);
    CHECK(text.find("track.keyframe record of kf1") != std::string::npos);
  }
}
