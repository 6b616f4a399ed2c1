// Lines and planes in the backbone (issue 13): config keys, association and landmark creation on
// a synthetic frame pair, bad input (unknown key, zero-length segment, zero normal, a frame whose
// depth is all zero), and mgd-nd runs end to end.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <set>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "io/trajectory.h"
#include "io/sequence.h"
#include "optim/optim.h"
#include "pipeline/method_config.h"
#include "pipeline/pipeline.h"
#include "features/lines.h"
#include "structure/line_frame_matching.h"
#include "structure/structure_tracker.h"
#include "synth/synth.h"
#include "test_support.h"
#include "io/image_file.h"

using namespace dynref;

namespace {

std::string WriteConfig(const std::string& name, const std::string& text) {
  const std::string path = test::ScratchDir("structure_" + name) + "/c.yaml";
  std::ofstream(path) << text;
  return path;
}

// A synthetic static sequence (cached per name within one test process).
std::string Synth(const std::string& name, const std::string& preset, int frames, uint64_t seed = 1) {
  const std::string dir = test::ScratchDir("structure_seq_" + name);
  synth::SynthOptions so;
  so.preset = preset;
  so.frames = frames;
  so.seed = seed;
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  return so.out;
}

// Frame k of a sequence, loaded and extracted as the frame loop does (grey = true luminance).
Frame LoadFrame(const Sequence& seq, size_t k, const structure::StructureTracker& st) {
  Frame f;
  f.index = static_cast<int>(k);
  f.rgb = dynref::ImageRead(seq.frames[k].rgb_path, cv::IMREAD_COLOR);
  const cv::Mat d16 = dynref::ImageRead(seq.frames[k].depth_path, cv::IMREAD_UNCHANGED);
  d16.convertTo(f.depth_m, CV_32F, 1.0 / seq.camera.depth_factor);
  cv::cvtColor(f.rgb, f.grey, cv::COLOR_BGR2GRAY);
  f.pyramid = ScalePyramid::Make(8, 1.2);
  f.FinishFeatures(seq.camera);  // no keypoints: image bounds only
  st.Extract(f);
  return f;
}

}  // namespace

TEST_CASE("structure: line/plane backbone keys resolve with sources, unknown ones are errors with file:line") {
  const MethodConfig nd = LoadMethodConfig(test::SourcePath("configs/mgd_nd.yaml"));
  CHECK(nd.method == "mgd-nd");
  CHECK(nd.backbone.structure.lines);
  CHECK(nd.backbone.structure.planes);
  CHECK(nd.backbone.structure.line.parallel_deg == 3.0);
  CHECK(nd.backbone_params.at("line_match_bits").source.find("not stated") != std::string::npos);
  const MethodConfig orb = LoadMethodConfig(test::SourcePath("configs/orb.yaml"));
  CHECK_FALSE(orb.backbone.structure.enabled());  // the point-only backbone by default
  try {
    LoadMethodConfig(WriteConfig("badkey", "method: x\nbackbone:\n  lines: {value: true, source: s}\n  line_lenght_px: {value: 3, source: s}\n"));
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == 4);
    CHECK(std::string(e.what()).find("line_lenght_px") != std::string::npos);
  }
  CHECK_THROWS_AS(LoadMethodConfig(WriteConfig("range", "method: x\nbackbone:\n  line_match_bits: {value: 300, source: s}\n")),
                  InputError);
  // --set backbone.KEY re-validates.
  MethodConfig c = nd;
  c.SetBackboneParam("line_parallel_term", "false", "test");
  CHECK_FALSE(c.backbone.structure.line_parallel_term);
  CHECK_THROWS_AS(c.SetBackboneParam("line_max", "0", "test"), InputError);
  CHECK_THROWS_AS(c.SetBackboneParam("no_such_key", "1", "test"), InputError);
}

TEST_CASE("structure: frame lines get 3-D samples, landmarks are created at a keyframe and re-associated next frame", "[cli]") {
  const std::string seq_dir = Synth("pair", "static_xyz", 3);
  const Sequence seq = OpenSequence(seq_dir, SequenceOptions{});
  const MethodConfig cfg = LoadMethodConfig(test::SourcePath("configs/mgd_nd.yaml"));
  trace::TraceWriter trace("", trace::Level::kOff, trace::RunHeader{});
  const structure::StructureTracker st(seq.camera, cfg.backbone.structure, trace);
  Frame f0 = LoadFrame(seq, 0, st);
  REQUIRE(f0.structure.lines.size() > 50);
  REQUIRE(f0.structure.planes.size() >= 3);
  int with3d = 0;
  for (const FrameLine& L : f0.structure.lines) {
    CHECK(std::fabs(L.l.head<2>().norm() - 1) < 1e-9);
    CHECK(std::fabs(L.l.dot(Eigen::Vector3d(L.s.x(), L.s.y(), 1))) < 1e-6);
    with3d += L.has_3d;
  }
  CHECK(with3d > static_cast<int>(f0.structure.lines.size()) / 2);

  // Keyframe 0 at the ground-truth pose (identity): every 3-D line and every plane becomes a landmark.
  Map map;
  f0.T_cw = SE3::Identity();
  auto kf = std::make_unique<KeyFrame>();
  kf->frame = f0;
  KeyFrame* k = map.AddKeyFrame(std::move(kf));
  st.CreateLandmarks(f0, *k, map);
  CHECK(static_cast<int>(map.GoodLineCount()) == with3d);
  CHECK(map.GoodPlaneCount() == f0.structure.planes.size());

  // Frame 1 at its true pose relative to frame 0 associates most of them; frame 0 itself all of them.
  Frame again = LoadFrame(seq, 0, st);
  again.T_cw = SE3::Identity();
  st.Associate(again, map);
  int assoc = 0;
  for (size_t i = 0; i < again.structure.lines.size(); ++i) {
    if (!again.structure.lines[i].has_3d) continue;
    CHECK(again.structure.map_line_ids[i] >= 0);
    assoc += again.structure.map_line_ids[i] >= 0;
  }
  CHECK(assoc == with3d);
  for (int64_t id : again.structure.map_plane_ids) CHECK(id >= 0);

  const std::vector<std::pair<double, SE3>> gt = [&] {
    std::vector<std::pair<double, SE3>> out;
    std::ifstream in(seq_dir + "/groundtruth.txt");
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream ss(line);
      double t, x, y, z, qx, qy, qz, qw;
      ss >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
      out.push_back({t, MakeSE3(Eigen::Vector3d(x, y, z), Eigen::Quaterniond(qw, qx, qy, qz))});
    }
    return out;
  }();
  REQUIRE(gt.size() >= 2);
  Frame f1 = LoadFrame(seq, 1, st);
  f1.T_cw = gt[1].second.inverse() * gt[0].second;  // T_c1w with world = camera 0
  const double weighted = st.Associate(f1, map);
  int lines1 = 0, planes1 = 0;
  for (int64_t id : f1.structure.map_line_ids) lines1 += id >= 0;
  for (int64_t id : f1.structure.map_plane_ids) planes1 += id >= 0;
  CHECK(lines1 > with3d / 2);
  CHECK(planes1 >= 3);
  CHECK(weighted == Approx(lines1 * 1.0 + planes1 * 3.0));
  // Pose-only optimisation from lines and planes alone stays at the true pose.
  std::vector<int> li, pi;
  {  // the per-line weight hook reaches the residual
    Frame w = f1;
    REQUIRE(st.BuildPoseStructure(w, map, &li, &pi).lines.size() > 0);
    w.structure.line_weight[static_cast<size_t>(li[0])] = 0.25;
    CHECK(st.BuildPoseStructure(w, map, &li, &pi).lines[0].weight == 0.25);
    // Weight 0 (a dynamic method's "out"): no residual, no association, no landmark.
    const size_t out = static_cast<size_t>(li[0]);
    const int64_t was = w.structure.map_line_ids[out];
    const size_t n_res = st.BuildPoseStructure(w, map, &li, &pi).lines.size();
    w.structure.line_weight[out] = 0.0;
    CHECK(st.BuildPoseStructure(w, map, &li, &pi).lines.size() == n_res - 1);
    CHECK(std::find(li.begin(), li.end(), static_cast<int>(out)) == li.end());
    st.Associate(w, map);
    CHECK(w.structure.map_line_ids[out] == -1);
    w.structure.map_line_ids[out] = was;  // even when associated before, a keyframe does not observe it
    auto kf1 = std::make_unique<KeyFrame>();
    kf1->frame = w;
    KeyFrame* k1 = map.AddKeyFrame(std::move(kf1));
    const size_t lines_before = map.GoodLineCount();
    st.CreateLandmarks(w, *k1, map);
    CHECK(map.good_line(was)->observations.count(k1->id) == 0);
    for (const auto& [id, L] : map.lines) CHECK((L->first_kf != k1->id || L->observations.begin()->second != static_cast<int>(out)));
    CHECK(map.GoodLineCount() >= lines_before);
  }
  const optim::PoseStructure ps = st.BuildPoseStructure(f1, map, &li, &pi);
  const optim::PoseOnlyResult r = optim::OptimizePose(seq.camera.Pinhole(), f1.T_cw, {}, &ps, optim::PoseOnlyOptions{}, nullptr, "t");
  CHECK((r.T_cw.translation() - f1.T_cw.translation()).norm() < 0.01);
  CHECK(r.line_inliers > lines1 * 3 / 4);
}

TEST_CASE("structure: zero-length lines and zero normals are refused by name") {
  optim::PoseStructure ps;
  optim::LineObservation o;
  o.X_w = {Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0.1, 0, 2), Eigen::Vector3d(0.2, 0, 2)};
  o.l = Eigen::Vector3d::Zero();  // a segment whose two endpoints coincide
  o.obs_id = "ml7@f3";
  ps.lines.push_back(o);
  Intrinsics K;
  K.fx = K.fy = 500, K.cx = 320, K.cy = 240;
  try {
    optim::OptimizePose(K, SE3::Identity(), {}, &ps, optim::PoseOnlyOptions{}, nullptr, "t");
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("ml7@f3") != std::string::npos);
  }
  optim::PoseStructure pp;
  optim::PlaneObservationResidual p;
  p.n_w = Eigen::Vector3d::Zero();
  p.obs_id = "mpl1@f3";
  pp.planes.push_back(p);
  CHECK_THROWS_AS(optim::OptimizePose(K, SE3::Identity(), {}, &pp, optim::PoseOnlyOptions{}, nullptr, "t"), InputError);
  Map map;
  CHECK_THROWS_AS(map.NewMapPlane(Eigen::Vector3d::Zero(), 1.0, 0, 0), std::invalid_argument);
  CHECK(features::LineThrough({5, 5}, {5, 5}).isZero());
}

TEST_CASE("structure: mgd-nd survives a frame whose depth is all zero and reruns byte-identically", "[cli]") {
  const std::string seq_dir = Synth("zero_depth", "static_xyz", 20);
  const Sequence seq = OpenSequence(seq_dir, SequenceOptions{});
  const cv::Mat d = dynref::ImageRead(seq.frames[10].depth_path, cv::IMREAD_UNCHANGED);
  dynref::ImageWrite(seq.frames[10].depth_path, cv::Mat::zeros(d.size(), d.type()));
  std::string trajectories[2], dirs[2];
  for (int rep = 0; rep < 2; ++rep) {
    RunOptions ro;
    ro.sequence = seq_dir;
    ro.out_dir = dirs[rep] = test::ScratchDir("structure_zero_depth_run" + std::to_string(rep));
    ro.method = "mgd-nd";
    ro.trace_level = "full";
    ro.progress = false;
    const RunResult r = RunSequence(ro);
    CHECK(r.exit_code == 0);
    CHECK(r.frames == 20);
    CHECK(r.tracked >= 19);
    std::ifstream in(ro.out_dir + "/trajectory.txt");
    trajectories[rep].assign(std::istreambuf_iterator<char>(in), {});
  }
  CHECK(trajectories[0] == trajectories[1]);
  const test::CommandResult d2 = test::RunDynref("diff " + dirs[0] + " " + dirs[1]);
  INFO(d2.output);
  CHECK(d2.exit_code == 0);
}

TEST_CASE("structure: frame-to-frame line matching (shared map line, LBD + angle + distance gates, direction)") {
  const std::string seq_dir = Synth("pair", "static_xyz", 3);
  const Sequence seq = OpenSequence(seq_dir, SequenceOptions{});
  const MethodConfig cfg = LoadMethodConfig(test::SourcePath("configs/mgd_nd.yaml"));
  trace::TraceWriter trace("", trace::Level::kOff, trace::RunHeader{});
  const structure::StructureTracker st(seq.camera, cfg.backbone.structure, trace);
  const Frame f0 = LoadFrame(seq, 0, st), f1 = LoadFrame(seq, 1, st);
  const structure::LineMatchGates gates;
  // A frame against itself: every line with a line finds itself, distance 0, same direction.
  const auto self = structure::MatchLinesToPrevious(f0.structure, f0.structure, gates);
  for (size_t i = 0; i < self.size(); ++i) {
    if (f0.structure.lines[i].l.head<2>().squaredNorm() == 0) continue;
    CHECK(self[i].prev_index == static_cast<int>(i));
    CHECK(self[i].hamming == 0);
    CHECK_FALSE(self[i].reversed);
    CHECK(self[i].source == 1);
  }
  // The next frame (camera moved a few mm): most lines match by descriptor, each previous line once.
  const auto next = structure::MatchLinesToPrevious(f1.structure, f0.structure, gates);
  std::set<int> used;
  int matched = 0;
  for (const auto& c : next) {
    if (c.prev_index < 0) continue;
    ++matched;
    CHECK(used.insert(c.prev_index).second);
    CHECK(c.hamming <= gates.max_bits);
  }
  CHECK(matched > static_cast<int>(f1.structure.lines.size()) / 2);
  // A shared map line wins over every gate; a reversed copy is detected.
  FrameStructure a, b;
  FrameLine L;
  L.s = {100, 100}, L.e = {200, 100}, L.l = features::LineThrough(L.s, L.e), L.angle = 0;
  FrameLine far = L;
  far.s = {100, 300}, far.e = {200, 300}, far.l = features::LineThrough(far.s, far.e);
  FrameLine rev = L;
  rev.s = {203, 102}, rev.e = {103, 102}, rev.l = features::LineThrough(rev.s, rev.e);
  a.lines = {far, rev};
  b.lines = {L};
  a.line_descriptors = cv::Mat(2, 32, CV_8U, cv::Scalar(0));
  b.line_descriptors = cv::Mat(1, 32, CV_8U, cv::Scalar(0));
  a.map_line_ids = {-1, -1};
  b.map_line_ids = {-1};
  auto c = structure::MatchLinesToPrevious(a, b, gates);
  CHECK(c[0].prev_index == -1);  // 200 px away
  CHECK(c[1].prev_index == 0);
  CHECK(c[1].reversed);
  CHECK(c[1].source == 1);
  a.line_descriptors.row(1).setTo(0xFF);  // 256 bits: beyond the gate
  CHECK(structure::MatchLinesToPrevious(a, b, gates)[1].prev_index == -1);
  a.map_line_ids = {7, -1};  // the far line observes the previous line's map line
  b.map_line_ids = {7};
  c = structure::MatchLinesToPrevious(a, b, gates);
  CHECK(c[0].prev_index == 0);
  CHECK(c[0].source == 0);
}

TEST_CASE("structure: end to end in the plain room orb never starts and mgd-nd tracks every frame within 1 cm (issue 13)", "[e2e]") {
  // static_lowtexture: about 240 ORB keypoints with depth, so ORB-SLAM2's start rule (> 500)
  // never holds; mgd-nd starts on > 50 (configs/mgd_nd.yaml) and tracks on points, lines and
  // planes. 90 frames of seeds 1 and 3 (seed 3 has the fewest keypoints with depth).
  const uint64_t seed = GENERATE(uint64_t{1}, uint64_t{3});
  const std::string name = "lowtexture_s" + std::to_string(seed);
  const std::string seq_dir = Synth(name, "static_lowtexture", 90, seed);
  for (const std::string method : {"orb", "mgd-nd"}) {
    RunOptions ro;
    ro.sequence = seq_dir;
    ro.out_dir = test::ScratchDir("structure_" + name + "_" + method);
    ro.method = method;
    ro.progress = false;
    const RunResult r = RunSequence(ro);
    REQUIRE(r.frames == 90);
    if (method == "orb") {
      CHECK(r.tracked == 0);
      CHECK(r.end_state.rfind("never-initialised", 0) == 0);
      continue;
    }
    REQUIRE(r.exit_code == 0);
    CHECK(r.tracked == 90);
    const AteResult ate = ComputeAte(ReadTumTrajectory(seq_dir + "/groundtruth.txt"),
                                     ReadTumTrajectory(ro.out_dir + "/trajectory.txt"), AteOptions{});
    INFO("seed " << seed << " ATE " << ate.stats.rmse);
    CHECK(ate.matches.size() == 90);
    CHECK(ate.stats.rmse < 0.01);
  }
}
