// MGD-SLAM stages (seed 000): previous-frame correspondences, the P_pro cache through landmark
// events, and the method end to end on a synthetic walking sequence.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>

#include "dynamic/mgd/correspondence.h"
#include "dynamic/mgd/stages.h"
#include "method_e2e.h"
#include "pipeline/method_config.h"
#include "reproduce/workspace.h"
#include "trace/trace_reader.h"
#include "test_support.h"

using namespace dynref;

namespace {

// A frame with the given undistorted keypoints, descriptors (row i filled with byte fill[i]),
// map points and no exclusions.
Frame MakeFrame(const std::vector<cv::Point2f>& pts, const std::vector<uint8_t>& fill, const std::vector<int64_t>& mps) {
  Frame f;
  for (const auto& p : pts) f.keys.emplace_back(p, 7.f);
  f.keys_un = f.keys;
  f.descriptors = cv::Mat(static_cast<int>(pts.size()), 32, CV_8U);
  for (int i = 0; i < f.descriptors.rows; ++i) f.descriptors.row(i).setTo(fill[i]);
  f.map_point_ids = mps;
  f.outlier.assign(pts.size(), 0);
  f.depth.assign(pts.size(), 1.f);
  f.u_right.assign(pts.size(), -1.f);
  return f;
}

}  // namespace

TEST_CASE("mgd correspondences: shared map point first, else the closest descriptor in the window") {
  // Previous frame: 0 sees map point 9; 1 and 2 have no map point.
  const Frame prev = MakeFrame({{100, 100}, {200, 200}, {205, 200}}, {0x00, 0x0F, 0xFF}, {9, -1, -1});
  // Current: 0 sees map point 9 (descriptor 1 bit off per byte = 32 bits); 1 near prev 1/2 with
  // descriptor 0x0F (= prev 1 exactly); 2 far from everything; 3 near prev 2 but 0x00 vs 0xFF.
  Frame cur = MakeFrame({{300, 300}, {203, 201}, {600, 400}, {206, 201}}, {0x01, 0x0F, 0x0F, 0x00}, {9, -1, -1, -1});
  const auto c = mgd::MatchPrevious(cur, prev, 0.6, 40);
  CHECK(c[0].prev_index == 0);  // by map point, although 200 px away
  CHECK(c[0].source == mgd::CorrespondenceSource::kMapPoint);
  CHECK(c[0].hamming == 32);
  CHECK(c[1].prev_index == 1);  // closest descriptor, not the closest point (prev 2 is nearer)
  CHECK(c[1].source == mgd::CorrespondenceSource::kDescriptorWindow);
  CHECK(c[1].hamming == 0);
  CHECK(c[2].prev_index == -1);  // nothing within 40 px
  // prev 2 = 0xFF vs 0x00: 256 bits; prev 1 = 0x0F vs 0x00: 128 bits > (1 - 0.6) 256 = 102 bits.
  CHECK(c[3].prev_index == -1);
  // delta 0.4 accepts up to 153 bits: now prev 1 (128) matches feature 3.
  CHECK(mgd::MatchPrevious(cur, prev, 0.4, 40)[3].prev_index == 1);
}

TEST_CASE("mgd P_pro cache follows replaced and culled map points") {
  auto state = std::make_shared<mgd::MgdState>();
  mgd::ReprojectionStage stage(state);
  state->pro[5] = {1, 1, 0.2, 2, 0};
  state->pro[8] = {9, 9, 0.9, 2, 0};
  LandmarkEvent e;
  e.kind = LandmarkEvent::Kind::kReplaced;
  e.landmark = {LandmarkType::kPoint, 5};
  e.by_id = 7;  // 7 has no value: it takes 5's
  stage.OnLandmarkEvent(e);
  CHECK(state->pro.count(5) == 0);
  REQUIRE(state->pro.count(7) == 1);
  CHECK(state->pro.at(7).p == 0.2);
  e.landmark.id = 7;
  e.by_id = 8;  // 8 keeps its own value
  stage.OnLandmarkEvent(e);
  CHECK(state->pro.at(8).p == 0.9);
  CHECK(state->pro.count(7) == 0);
  e.kind = LandmarkEvent::Kind::kCulled;
  e.landmark.id = 8;
  stage.OnLandmarkEvent(e);
  CHECK(state->pro.empty());
}

// Issue 38: "people rejected" is checked on the rejected features themselves (precision / recall
// against the ground truth's moving instances, as the reproduce tables count them), not only
// through the ATE: with mgd.probability's exclusion planted out (no feature rejected, the 1 - P
// weights left) the ATE checks still passed (0.0203 m, orb 0.355 m) and the recall check failed.
TEST_CASE("mgd end to end: people rejected, ATE far below orb's on synthetic walking_xyz", "[e2e]") {
  reproduce::SynthSpec spec;
  spec.frames = 60, spec.seed = 3;
  reproduce::Workspace ws(test::ScratchDir("mgd_e2e"), spec, false);
  const std::string seq = ws.EnsureSequence("walking_xyz");
  const reproduce::RunSummary orb = ws.Run(seq, "orb", LoadMethodConfig(test::SourcePath("configs/orb.yaml")), "orb");
  const reproduce::RunSummary mgd = ws.Run(seq, "mgd", LoadMethodConfig(test::SourcePath("configs/mgd.yaml")), "mgd");
  REQUIRE(orb.has_ate);
  REQUIRE(mgd.has_ate);
  REQUIRE(mgd.has_pr);
  const double precision = double(mgd.tp) / double(mgd.tp + mgd.fp), recall = double(mgd.tp) / double(mgd.tp + mgd.fn);
  INFO("ATE orb " << orb.ate.rmse << " mgd " << mgd.ate.rmse << "; rejected tp " << mgd.tp << " fp " << mgd.fp << " fn "
                  << mgd.fn << ": precision " << precision << " recall " << recall);
  CHECK(mgd.tracked == 60);
  CHECK(mgd.ate.rmse < 0.03);
  CHECK(mgd.ate.rmse < 0.25 * orb.ate.rmse);
  CHECK(recall > 0.75);  // measured 0.853 (tp 16794, fn 2896)
  CHECK(precision > 0.5);  // measured 0.570 (fp 12665)
}

namespace {

// Runs configs/mgd.yaml (300 features, after_local_map_search as given) on `seq` with a full
// trace; returns {final map-point observations, of them the ones mgd.inherit saw with another
// (or no) map point}.
std::pair<int, int> MgdAssociationsMissed(const test::E2eSequence& seq, bool after_local_map_search, const std::string& out) {
  auto cfg = std::make_shared<MethodConfig>(LoadMethodConfig(test::SourcePath("configs/mgd.yaml")));
  cfg->ApplySets({"backbone.n_features=300", std::string("mgd.probability.after_local_map_search=") +
                                                 (after_local_map_search ? "true" : "false")},
                 "test");
  RunOptions o;
  o.sequence = seq.synth.out;
  o.out_dir = out;
  o.method = "mgd";
  o.config = cfg;
  o.detections_dir = seq.detections_dir;
  o.trace_level = "full";
  o.progress = false;
  REQUIRE(RunSequence(o).exit_code == 0);
  trace::TraceReader reader(out + "/trace.dtr");
  int observed = 0, missed = 0;
  int64_t newest_before = -1;  // map point ids are increasing: newer ones did not exist yet
  for (size_t g = 0; g < reader.groups().size(); ++g) {
    std::map<std::string, int64_t> seen;  // feature id -> map point mgd.inherit saw
    std::vector<std::pair<std::string, int64_t>> final_obs;
    for (const trace::Record& r : reader.ReadGroup(g)) {
      if (r.type == trace::RecordType::kProbability && r.stage == "mgd.inherit")
        for (const auto& in : r.inputs)
          if (in.name == "map_point") seen[r.entity] = static_cast<int64_t>(in.value);
      if (r.type == trace::RecordType::kObservation && r.map_point_id >= 0)
        final_obs.emplace_back("f" + std::to_string(r.frame) + "." + std::to_string(r.feature_index), r.map_point_id);
    }
    for (const auto& [id, mp] : seen) newest_before = std::max(newest_before, mp);
    if (!seen.empty())  // the initialisation frame has no inheritance
      for (const auto& [id, mp] : final_obs) {
        if (mp > newest_before) continue;  // made by this frame's keyframe, after the update
        ++observed;
        auto it = seen.find(id);
        missed += it == seen.end() || it->second != mp;
      }
    for (const auto& [id, mp] : final_obs) newest_before = std::max(newest_before, mp);
  }
  return {observed, missed};
}

}  // namespace

// Issue 38: the paper (Sec. 3.4) updates "a 3D map point observed in F_k" from "the corresponding
// map representation", so every feature that ends the frame on a map point must have inherited
// from that point. Run right after the initial pose (the old order) the update misses the
// local-map search's associations (49 % of golden/mgd_30f's).
TEST_CASE("mgd probability runs after the local-map search: it sees every final map-point association", "[e2e]") {
  const std::string dir = test::ScratchDir("mgd_after_local_map");
  const test::E2eSequence seq = test::MakeE2eSequence(dir, 12, 1, "yolo-like", false);
  const auto [observed, missed] = MgdAssociationsMissed(seq, true, dir + "/after");
  INFO("final map-point observations " << observed << ", missed by mgd.inherit " << missed);
  CHECK(observed > 300);
  CHECK(missed == 0);
  const auto [observed_old, missed_old] = MgdAssociationsMissed(seq, false, dir + "/before");
  INFO("old order: " << observed_old << " observations, " << missed_old << " missed");
  CHECK(missed_old > observed_old / 5);
}
