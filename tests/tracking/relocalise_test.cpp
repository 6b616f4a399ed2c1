// Relocalisation (ORB-SLAM2 Tracking::Relocalization with brute-force candidates and seeded PnP
// RANSAC) on the real TUM fr1 frames: a frame of the mapped scene is relocalised near its true
// pose; a frame of another scene is not.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "core/rng.h"
#include "features/orb_extractor.h"
#include "io/sequence.h"
#include "io/trajectory.h"
#include "trace/trace_reader.h"
#include "mapping/local_mapper.h"
#include "tracking/real_frames.h"
#include "tracking/tracker.h"
#include "test_support.h"

using namespace dynref;

namespace {

Frame Load(const Sequence& seq, int i, features::OrbExtractor& ex) { return test::LoadRealFrame(seq, i, ex); }

}  // namespace

TEST_CASE("relocalisation: a mapped view is recovered, an unrelated view is not") {
  const Sequence seq = OpenSequence(test::SourcePath("datasets/real/tum_fr1_desk_9frames"));
  features::OrbExtractor ex{features::OrbOptions{}};
  const std::string dir = test::ScratchDir("relocalise_candidates");
  trace::TraceWriter trace{dir + "/trace.dtr", trace::Level::kFrames, trace::RunHeader{}};
  Map map;
  tracking::Tracker tracker{seq.camera, map, tracking::TrackerOptions{}, trace};
  mapping::LocalMapper mapper{map, seq.camera, mapping::LocalMapperOptions{}, trace};
  Frame f0 = Load(seq, 0, ex);
  trace.BeginFrame(0, f0.stamp);
  KeyFrame* kf = tracker.TryInitialise(f0);
  REQUIRE(kf != nullptr);
  mapper.ProcessKeyFrame(kf->id);
  tracker.FinishFrame(f0, true);
  // Frame 1 with every feature excluded: lost.
  Frame f1 = Load(seq, 1, ex);
  trace.BeginFrame(1, f1.stamp);
  for (size_t i = 0; i < f1.N(); ++i) f1.Exclude(static_cast<int>(i), "test", "all");
  REQUIRE_FALSE(tracker.TrackInitial(f1));
  tracker.FinishFrame(f1, false);
  REQUIRE(tracker.state() == tracking::TrackState::kLost);
  // An unrelated view: seeded random texture at 2 m (frame 2's image rotated by 180 degrees would
  // not do: ORB is rotation invariant and that is the same desk seen with the camera rolled).
  Frame odd = Load(seq, 2, ex);
  Rng rng(7, "test.texture");
  cv::Mat noise(odd.grey.size(), CV_8U);
  for (int y = 0; y < noise.rows; ++y)
    for (int x = 0; x < noise.cols; ++x) noise.at<uint8_t>(y, x) = static_cast<uint8_t>(rng.UniformInt(0, 255));
  cv::GaussianBlur(noise, noise, cv::Size(5, 5), 1.5);
  odd.keys.clear();
  ex.Extract(noise, &odd.keys, &odd.descriptors);
  odd.depth_m.setTo(2.0f);
  odd.FinishFeatures(seq.camera);
  REQUIRE(odd.N() > 500);
  trace.BeginFrame(2, odd.stamp);
  CHECK_FALSE(tracker.TrackInitial(odd));
  tracker.FinishFrame(odd, false);
  // Frame 3 of the mapped desk: relocalised, close to the ground-truth motion from frame 0.
  Frame f3 = Load(seq, 3, ex);
  trace.BeginFrame(3, f3.stamp);
  REQUIRE(tracker.TrackInitial(f3));
  const TumTrajectory gt = ReadTumTrajectory(test::SourcePath("datasets/real/tum_fr1_desk_9frames/groundtruth.txt"));
  // Relative motion frame 0 -> 3 from the estimate vs the ground truth nearest to the stamps.
  auto nearest = [&](double t) {
    size_t best = 0;
    for (size_t i = 1; i < gt.poses.size(); ++i)
      if (std::abs(gt.poses[i].stamp - t) < std::abs(gt.poses[best].stamp - t)) best = i;
    return gt.poses[best].T_wc.inverse();  // T_cw
  };
  const SE3 est_rel = f3.T_cw * f0.T_cw.inverse();
  const SE3 gt_rel = nearest(f3.stamp) * nearest(f0.stamp).inverse();
  INFO("estimated " << est_rel.translation().transpose() << " ground truth " << gt_rel.translation().transpose());
  CHECK((est_rel.translation() - gt_rel.translation()).norm() < 0.02);
  int matched = 0;
  for (size_t i = 0; i < f3.N(); ++i) matched += f3.map_point_ids[i] >= 0 && !f3.outlier[i];
  CHECK(matched >= 50);
  // Each tried candidate leaves its keyframe and how far it got (-1 = step not reached): the
  // unrelated view fails every one short of 50 inliers, frame 3's last one reaches them.
  trace.Close("complete");
  trace::TraceReader reader(dir + "/trace.dtr");
  auto candidates = [&](size_t group) {
    std::vector<std::pair<std::string, int64_t>> out;
    for (const trace::Record& r : reader.ReadGroup(group))
      if (r.type == trace::RecordType::kCount && r.stage == "track.reloc" && r.name.rfind("candidate_", 0) == 0)
        out.emplace_back(r.name, r.value);
    return out;
  };
  const auto odd_records = candidates(2), f3_records = candidates(3);
  REQUIRE(!odd_records.empty());
  REQUIRE(odd_records.size() % 4 == 0);
  for (size_t k = 0; k < odd_records.size(); k += 4) {
    CHECK(odd_records[k].first == "candidate_kf");
    CHECK(odd_records[k + 3].first == "candidate_inliers");
    CHECK(odd_records[k + 3].second < 50);
  }
  REQUIRE(f3_records.size() >= 4);
  CHECK(f3_records[f3_records.size() - 4].second == kf->id);
  CHECK(f3_records[f3_records.size() - 2].second > 0);   // PnP inliers
  CHECK(f3_records.back().second >= 50);
}
