// Tests of the blur verifiers (ref/verify/README.md, "Motion-blur SLAM"): a hand-built four-frame
// trace (a person found, lost and pasted at the least-squares prediction, its track ended, a new
// person fused with depth, keypoints scored by their neighbours) verifies; planted wrong records
// (an `after` changed, an input removed, a reason changed) are named.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/rng.h"
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

struct BlurPlant {
  std::string stage, entity;
  std::string drop_input;
  double after_delta = 0;
  std::string reason;  // replaces the reason of a DECISION on `entity`
};

nlohmann::json BlurParam(const nlohmann::json& v) { return {{"value", v}, {"source", "test"}}; }

std::string BlurConfig() {
  nlohmann::json c;
  c["method"] = "blur";
  c["stages"] = nlohmann::json::array(
      {{{"name", "blur.mask"},
        {"params",
         {{"compensation", BlurParam(true)}, {"r_threshold", BlurParam(0.9)}, {"history", BlurParam(3)},
          {"iou_found", BlurParam(0.3)}, {"max_consecutive", BlurParam(1)}, {"depth_fusion", BlurParam(true)},
          {"grid_cols", BlurParam(4)}, {"grid_rows", BlurParam(3)}, {"samples_per_cell", BlurParam(1)},
          {"alpha_m", BlurParam(0.3)}, {"sigma_mult", BlurParam(3.0)}, {"dilation_size", BlurParam(2)},
          {"sampling_seed", BlurParam(7)}}}},
       {{"name", "blur.probability"},
        {"params",
         {{"compute", BlurParam(true)}, {"radius_px", BlurParam(20)}, {"c1", BlurParam(1.0)}, {"c2", BlurParam(0.05)},
          {"theta", BlurParam(0.2)}}}}});
  return c.dump();
}

// Stratified samples of the first fused frame: 4 x 3 cells of 40 x 40 px, one per cell, row
// then column drawn from Rng(7, "blur.depth_sampling"); how many fall in [x0, x1] x [y0, y1].
int BlurInBox(int x0, int y0, int x1, int y1) {
  dynref::Rng rng(7, "blur.depth_sampling");
  int n = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      const int64_t y = rng.UniformInt(r * 40, r * 40 + 39), x = rng.UniformInt(c * 40, c * 40 + 39);
      n += x >= x0 && x <= x1 && y >= y0 && y <= y1;
    }
  return n;
}

std::string BlurWriteTrace(const std::string& dir, const BlurPlant& plant) {
  dynref::trace::RunHeader h;
  h.method = "blur";
  h.config_json = BlurConfig();
  h.extra.emplace_back("camera_json", R"({"fx":100,"fy":100,"cx":80,"cy":60,"bf":40,"th_depth":40,"width":160,"height":120})");
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
  auto decision = [&](const std::string& stage, EntityKind kind, const std::string& id, std::string reason) {
    if (plant.stage == stage && plant.entity == id && !plant.reason.empty()) reason = plant.reason;
    w.Decision(stage, kind, id, false, reason);
  };
  auto counts = [&](int now, int before, int after, int comp, int depth, int dil) {
    for (const auto& [k, v] : std::vector<std::pair<std::string, int>>{{"area_now", now}, {"area_before", before},
                                                                       {"area_after", after}, {"px_segmenter", after - comp},
                                                                       {"px_compensation", comp}, {"px_depth_fusion", depth},
                                                                       {"px_dilation", dil}})
      w.FrameCount("blur.mask", k, v);
  };
  auto person = [&](const std::string& id, double track, double found, double iou, Inputs box, double t) {
    Inputs in = {{"track", track}, {"found", found}, {"iou", iou}};
    in.insert(in.end(), box.begin(), box.end());
    in.push_back({"t", t});
    prob("blur.compensation", EntityKind::kInstanceMask, id, in, 1, 1);
  };
  const auto box = [](double x0, double y0, double x1, double y1) {
    return Inputs{{"x_min", x0}, {"y_min", y0}, {"x_max", x1}, {"y_max", y1}};
  };
  // Frame 0: person 1 (30 x 50 px) starts track 1.
  w.BeginFrame(0, 0.0);
  counts(1500, 0, 1500, 0, 0, 300);
  person("i0.1", 1, 0, 0, box(10, 10, 39, 59), 0.0);
  // Frame 1: found again, moved 2 px right (IoU 1400 / 1600).
  w.BeginFrame(1, 0.1);
  counts(1500, 1500, 1500, 0, 0, 300);
  person("i1.1", 1, 1, 0.875, box(12, 10, 41, 59), 0.1);
  // Frame 2: missed (r = 0 < 0.9): the line through (10, 10, 0) and (12, 10, 0.1) gives (14, 10).
  w.BeginFrame(2, 0.2);
  counts(0, 1500, 1500, 1500, 0, 300);
  Inputs paste = {{"track", 1}, {"samples", 2}, {"x0", 10}, {"y0", 10}, {"t0", 0.0}, {"x1", 12}, {"y1", 10}, {"t1", 0.1},
                  {"t_c", 0.2}, {"from_x", 12}, {"from_y", 10}, {"to_x", 14}, {"to_y", 10}, {"dx", 2}, {"dy", 0}};
  for (const NamedValue& v : box(14, 10, 43, 59)) paste.push_back(v);
  paste.insert(paste.end(), {{"moved_px", 1500}, {"pasted_px", 1500}, {"consecutive", 1}});
  prob("blur.compensation", EntityKind::kPixelRegion, "r2.0", paste, 0, 1);
  // Frame 3: a new person elsewhere (r = 1600 / 1500, no trigger): track 1 ends, track 2 starts;
  // its box is fused with depth; keypoints 0, 1 in the mask, 2 and 3 scored by neighbours.
  w.BeginFrame(3, 0.3);
  counts(1600, 1500, 1600, 0, 50, 400);
  person("i3.4", 2, 0, 0, box(80, 40, 119, 79), 0.3);
  decision("blur.compensation", EntityKind::kPixelRegion, "r2.0", "lost:not-triggered");
  const int in_box = BlurInBox(80, 40, 119, 79);
  Inputs depth = box(80, 40, 119, 79);
  depth.insert(depth.begin(), {"box", 0});
  depth.insert(depth.end(), {{"in_box", double(in_box)}, {"samples", 1}, {"g_h", 2.0}, {"lo", 1.7}, {"hi", 2.3},
                             {"mu_box", 2.1}, {"sigma_box", 0.2}, {"box_valid_px", 1500}, {"fused_px", 900},
                             {"added_px", 50}, {"d0", 2.0}});
  prob("blur.depth_fusion", EntityKind::kPixelRegion, "r3.0", depth, 0, 1);
  auto keypoint = [&](int i, double x, double y, double n, double dyn, double pre, double post) {
    prob("blur.probability", EntityKind::kFeature, "f3." + std::to_string(i),
         {{"x", x}, {"y", y}, {"neighbours", n}, {"dynamic_neighbours", dyn}, {"radius_px", 20}, {"theta", 0.2}}, pre, post);
  };
  keypoint(0, 100, 50, 0, 0, 1, 1);
  decision("blur.probability", EntityKind::kFeature, "f3.0", "in-mask");
  keypoint(1, 110, 60, 0, 0, 1, 1);
  decision("blur.probability", EntityKind::kFeature, "f3.1", "in-mask");
  // f3.2: neighbours f3.1 (15 px, dynamic) and f3.3 (sqrt(250) px): P' = exp(-0.05 * 15) / 2.
  keypoint(2, 125, 60, 2, 1, 0, std::exp(-0.75) / 2);
  decision("blur.probability", EntityKind::kFeature, "f3.2", "probability>theta");
  // f3.3: its only neighbour f3.2 is static: P' = 0.
  keypoint(3, 130, 75, 1, 0, 0, 0);
  w.Close("complete");
  return path;
}

// A person crossing the image fast (300 px/s) is missed after a 0.9 s gap: the line fit puts it
// at x = 300, out of the 160 px image, so its track ends ("lost:outside-image"), nothing pasted.
std::string WriteLeavingTrace(const std::string& dir, const std::string& reason) {
  dynref::trace::RunHeader h;
  h.method = "blur";
  h.config_json = BlurConfig();
  h.extra.emplace_back("camera_json", R"({"fx":100,"fy":100,"cx":80,"cy":60,"bf":40,"th_depth":40,"width":160,"height":120})");
  const std::string path = dir + "/trace.dtr";
  dynref::trace::TraceWriter w(path, dynref::trace::Level::kFull, h);
  auto frame = [&](int f, double t, int now, int before, int after, int dil) {
    w.BeginFrame(f, t);
    for (const auto& [k, v] : std::vector<std::pair<std::string, int>>{{"area_now", now}, {"area_before", before},
                                                                       {"area_after", after}, {"px_segmenter", after},
                                                                       {"px_compensation", 0}, {"px_depth_fusion", 0},
                                                                       {"px_dilation", dil}})
      w.FrameCount("blur.mask", k, v);
  };
  frame(0, 0.0, 3000, 0, 3000, 200);
  w.ProbabilityUpdate("blur.compensation", EntityKind::kInstanceMask, "i0.1",
                      {{"track", 1}, {"found", 0}, {"iou", 0}, {"x_min", 0}, {"y_min", 10}, {"x_max", 59}, {"y_max", 59}, {"t", 0.0}},
                      1, 1);
  frame(1, 0.1, 3000, 3000, 3000, 200);
  w.ProbabilityUpdate("blur.compensation", EntityKind::kInstanceMask, "i1.1",
                      {{"track", 1}, {"found", 1}, {"iou", 1500.0 / 4500.0}, {"x_min", 30}, {"y_min", 10}, {"x_max", 89},
                       {"y_max", 59}, {"t", 0.1}},
                      1, 1);
  frame(2, 1.0, 0, 3000, 0, 0);
  w.Decision("blur.compensation", EntityKind::kInstanceMask, "i1.1", false, reason);
  w.Close("complete");
  return path;
}

dynref::verify::VerifyReport BlurVerify(const std::string& path) {
  return dynref::verify::test::VerifyWith(path, dynref::verify::AddBlurVerifiers);
}

using dynref::verify::test::Examples;

}  // namespace

TEST_CASE("verify blur: hand-built association, paste, track end, fusion and keypoint records verify", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_blur_ok");
  REQUIRE(BlurInBox(80, 40, 119, 79) >= 1);  // the box covers cell (2, 1) whole
  const dynref::verify::VerifyReport r = BlurVerify(BlurWriteTrace(dir, {}));
  INFO(Examples(r));
  CHECK(r.ok());
  CHECK(r.stages.at("blur.compensation").verified == 5);
  CHECK(r.stages.at("blur.depth_fusion").verified == 1);
  CHECK(r.stages.at("blur.probability").verified == 7);
}

TEST_CASE("verify blur: a planted wrong after, input or reason is named", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_blur_planted");
  struct Case { BlurPlant plant; std::string stage; bool mismatch; std::string fragment; };
  const std::vector<Case> cases = {
      {{"blur.compensation", "r2.0", "", -0.5, ""}, "blur.compensation", true, "r2.0 field after"},
      {{"blur.compensation", "r2.0", "t1", 0, ""}, "blur.compensation", false, "r2.0: not in the trace: input t1"},
      {{"blur.compensation", "r2.0", "", 0, "lost:outside-image"}, "blur.compensation", true, "r2.0 field reason"},
      {{"blur.compensation", "i1.1", "track", 0, ""}, "blur.compensation", false, "i1.1: not in the trace: input track"},
      {{"blur.depth_fusion", "r3.0", "", -1, ""}, "blur.depth_fusion", true, "r3.0 field after"},
      {{"blur.depth_fusion", "r3.0", "d0", 0, ""}, "blur.depth_fusion", false, "r3.0: not in the trace: input d0"},
      {{"blur.probability", "f3.2", "", 0.01, ""}, "blur.probability", true, "f3.2 field after"},
      {{"blur.probability", "f3.3", "x", 0, ""}, "blur.probability", false, "f3.3: not in the trace: input x"},
      {{"blur.probability", "f3.2", "", 0, "in-mask"}, "blur.probability", true, "f3.2 field reason"},
  };
  for (const Case& k : cases) {
    INFO(k.plant.stage + " " + k.plant.entity + " " + k.plant.drop_input + " " + k.plant.reason);
    const dynref::verify::VerifyReport r = BlurVerify(BlurWriteTrace(dir, k.plant));
    const std::string ex = Examples(r);
    INFO(ex);
    CHECK(!r.ok());
    const dynref::verify::StageReport& s = r.stages.at(k.stage);
    CHECK((k.mismatch ? s.mismatched : s.unverifiable) >= 1);
    CHECK(ex.find(k.fragment) != std::string::npos);
  }
}

TEST_CASE("verify blur: a track predicted out of the image ends as lost:outside-image", "[verify]") {
  const std::string dir = dynref::test::ScratchDir("verify_blur_leaving");
  const dynref::verify::VerifyReport ok = BlurVerify(WriteLeavingTrace(dir, "lost:outside-image"));
  INFO(Examples(ok));
  CHECK(ok.ok());
  CHECK(ok.stages.at("blur.compensation").verified == 3);
  const dynref::verify::VerifyReport bad = BlurVerify(WriteLeavingTrace(dir, "lost:not-triggered"));
  const std::string ex = Examples(bad);
  INFO(ex);
  CHECK(bad.stages.at("blur.compensation").mismatched == 1);
  CHECK(ex.find("i1.1 field reason") != std::string::npos);
}
