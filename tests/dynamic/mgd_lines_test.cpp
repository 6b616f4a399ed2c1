// MGD-SLAM line samples (seed 000 Sec. 3.4, spec step 11, E12): box flags per sample, the
// correspondence and cues of a planted line pair with hand-computed values in both cue forms
// (a flipped sign or a swapped sample fails), and the per-line decision with its write-back.
#include <catch2/catch.hpp>

#include "dynamic/mgd/line_samples.h"
#include "dynamic/mgd/stages.h"
#include "features/lines.h"

using namespace dynref;

namespace {

Camera LinesTestCamera() {
  Camera c = {};
  c.name = "test";
  c.width = 320, c.height = 240;
  c.fx = 250, c.fy = 250, c.cx = 160, c.cy = 120;
  return c;
}

FrameLine Line(Eigen::Vector2d s, Eigen::Vector2d e, const Camera& cam, double z) {
  FrameLine L;
  L.s = s, L.e = e;
  L.l = features::LineThrough(s, e);
  L.angle = 0;
  L.length = (e - s).norm();
  const Eigen::Vector2d px[3] = {s, 0.5 * (s + e), e};
  for (size_t k = 0; k < 3; ++k) {
    L.X_c[k] = cam.Pinhole().Backproject(px[k].x(), px[k].y(), z);
    L.sample_depth[k] = 1;
  }
  L.has_3d = true;
  return L;
}

void SetLines(Frame& f, int index, const std::vector<FrameLine>& lines) {
  f.index = index;
  f.structure.enabled = true;
  f.structure.lines = lines;
  f.structure.line_descriptors = cv::Mat(static_cast<int>(lines.size()), 32, CV_8U, cv::Scalar(0));
  f.structure.Reset(lines.size(), 0);
}

}  // namespace

TEST_CASE("mgd line samples: Flag_d per sample s, m, e") {
  const Camera cam = LinesTestCamera();
  Frame f;
  SetLines(f, 0, {Line({100, 100}, {200, 100}, cam, 2)});
  FrameDetections det;
  DetectedInstance person;
  person.class_id = 0, person.confidence = 0.9, person.x_min = 140, person.x_max = 250, person.y_min = 90, person.y_max = 110;
  det.instances = {person};
  f.detections = &det;
  mgd::MgdOptions o;
  const auto flags = mgd::LineSampleBoxFlags(f, o);
  REQUIRE(flags.size() == 1);
  CHECK(flags[0][0] == 0);  // s = (100, 100) outside
  CHECK(flags[0][1] == 1);  // m = (150, 100) inside
  CHECK(flags[0][2] == 1);  // e = (200, 100) inside
  det.instances[0].confidence = 0.5;  // not > 0.5: no kept box
  CHECK(mgd::LineSampleBoxFlags(f, o)[0][1] == 0);
}

TEST_CASE("mgd line samples: planted pair, reversed correspondence, hand-computed cues in both forms") {
  const Camera cam = LinesTestCamera();
  // Previous line (100,100)-(200,100) at 2 m; the current one moved 3 px down and was detected the
  // other way round: s' = (203,103) pairs with the previous e = (200,100), e' with the previous s.
  Frame prev, cur;
  SetLines(prev, 4, {Line({100, 100}, {200, 100}, cam, 2)});
  SetLines(cur, 5, {Line({203, 103}, {103, 103}, cam, 2)});
  Map map;
  trace::TraceWriter tr("", trace::Level::kOff, trace::RunHeader{});
  FrameEdit edit(cur, map, Hook::kAfterInitialPose);
  StageContext ctx{edit, &prev, nullptr, map, cam, tr, true, false};
  mgd::MgdOptions o;
  mgd::MgdState s;
  s.prev_frame = 4;
  s.prev_line_p = {{0.1, 0.2, 0.3}};
  s.line_in_box = {{0, 0, 0}};

  SECTION("pseudo-point form: the sample pair's own velocity and epipolar distance") {
    const Eigen::Vector2d vbar(1, 0);
    const mgd::LineSampleNodes n = mgd::EvaluateLineSamples(ctx, o, s, &vbar, nullptr, nullptr, "t");
    REQUIRE(n.size() == 1);
    CHECK(n.corr[0].prev_index == 0);
    CHECK(n.corr[0].reversed);
    // Sample s (k = 0) inherits the previous e's P = 0.3 (not s's 0.1).
    CHECK(n.p_prev[0][0] == 0.3);
    CHECK(n.p_prev[0][2] == 0.1);
    // k = 0: v = (203,103) - (200,100) = (3,3); v - vbar = (2,3): d = sqrt(13) = 3.605551;
    // dtheta = angle((3,3), (1,0)) = pi/4. P_LS = sig(0.5 (3.605551 - 3) + 0.5 (0.785398 - 2))
    // = sig(-0.304526) = 0.424452; no F: S = sig(0.4 logit P_LS) = sig(-0.121810) = 0.469584;
    // P = 0.3 * 0.3 + 0.7 * 0.469584 = 0.418709.
    CHECK(n.p_smooth[0][0] == Approx(0.418709).margin(1e-6));
    // m (k = 1): v = (153,103) - (150,100) = (3,3): same cues, inherits the previous m's 0.2:
    // 0.3 * 0.2 + 0.7 * 0.469584 = 0.388709.
    CHECK(n.p_smooth[0][1] == Approx(0.388709).margin(1e-6));
    CHECK(n.has_X[0][0]);
  }
  SECTION("normal form: normal flow against the mean, and the sample moved with its depth") {
    o.line_cue_form = mgd::LineCueForm::kNormal;
    // Mean flow 1 px down: the line's normal flow (3 px down) deviates by 2 px. dtheta is set to
    // theta_th (neutral): P_LS = sig(0.5 (2 - 3)) = sig(-0.5) = 0.377541.
    const Eigen::Vector2d vbar(0, 1);
    // No motion: the previous sample re-projects to itself, 3 px from the current line:
    // P_mf = sig(1 (3 - 2)) = sig(1) = 0.731059.
    const SE3 T = SE3::Identity();
    const mgd::LineSampleNodes n = mgd::EvaluateLineSamples(ctx, o, s, &vbar, nullptr, &T, "t");
    // S = sig(0.4 (-0.5) + 0.2 (1)) = sig(0) = 0.5; P = 0.3 * 0.3 + 0.7 * 0.5 = 0.44 (k = 0).
    CHECK(n.p_smooth[0][0] == Approx(0.44).margin(1e-9));
    CHECK(n.p_smooth[0][2] == Approx(0.3 * 0.1 + 0.7 * 0.5).margin(1e-9));
    // A mean flow 3 px down explains the line: d = 0, P_LS = sig(-1.5) = 0.182426;
    // S = sig(0.4 (-1.5) + 0.2) = sig(-0.4) = 0.401312; P = 0.09 + 0.7 * 0.401312 = 0.370918.
    const Eigen::Vector2d down3(0, 3);
    CHECK(mgd::EvaluateLineSamples(ctx, o, s, &down3, nullptr, &T, "t").p_smooth[0][0] ==
          Approx(0.370918).margin(1e-6));
  }
  SECTION("no correspondence: P_init by the sample's box flag, no cue") {
    cur.structure.line_descriptors.setTo(0xFF);  // 256 bits from the previous line
    s.line_in_box = {{1, 0, 0}};
    const Eigen::Vector2d vbar(1, 0);
    const mgd::LineSampleNodes n = mgd::EvaluateLineSamples(ctx, o, s, &vbar, nullptr, nullptr, "t");
    CHECK(n.corr[0].prev_index == -1);
    CHECK(n.p_prev[0][0] == 0.5);  // in a box
    CHECK(n.p_prev[0][1] == 0.0);
    // S = 0.5 (no cue): P = 0.3 P_init + 0.35.
    CHECK(n.p_smooth[0][0] == Approx(0.5));
    CHECK(n.p_smooth[0][1] == Approx(0.35));
  }
}

TEST_CASE("mgd line samples: a line is out above tau_dyn by its largest sample, else weight 1 - max P") {
  const Camera cam = LinesTestCamera();
  Frame f;
  SetLines(f, 3, {Line({100, 100}, {200, 100}, cam, 2), Line({100, 150}, {200, 150}, cam, 2)});
  Map map;
  MapLine* ml = map.NewMapLine(Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(1, 0, 2), cv::Mat(1, 32, CV_8U, cv::Scalar(0)), 0, 0);
  f.structure.map_line_ids = {-1, ml->id};
  trace::TraceWriter tr("", trace::Level::kOff, trace::RunHeader{});
  FrameEdit edit(f, map, Hook::kAfterInitialPose);
  StageContext ctx{edit, nullptr, nullptr, map, cam, tr, true, false};
  mgd::MgdOptions o;
  mgd::MgdState s;
  mgd::LineSampleNodes nodes;
  nodes.p_smooth = {{0.2, 0.6, 0.1}, {0.1, 0.2, 0.3}};
  const std::vector<double> p = {0.2, 0.6, 0.1, 0.1, 0.2, 0.3};
  CHECK(mgd::DecideLines(ctx, o, s, nodes, p, std::vector<int>(6, 0), "t") == 1);
  CHECK(f.structure.line_weight[0] == 0.0);
  CHECK(f.structure.line_weight[1] == Approx(0.7));
  CHECK(ml->dynamic.p_dynamic == 0.3);
  CHECK(s.prev_line_p[0][1] == 0.6);
  o.weight = mgd::WeightForm::kNone;
  mgd::DecideLines(ctx, o, s, nodes, p, std::vector<int>(6, 0), "t");
  CHECK(f.structure.line_weight[1] == 1.0);
  CHECK_THROWS_AS(mgd::DecideLines(ctx, o, s, nodes, {0.1}, {0}, "t"), std::logic_error);
  CHECK_THROWS_AS(edit.SetLineWeight(2, 0.5), std::logic_error);
  CHECK_THROWS_AS(edit.SetLineWeight(0, 1.5), std::logic_error);
  CHECK_THROWS_AS(edit.SetLineDynamicProbability(999, 0.5, "t"), std::logic_error);
}
