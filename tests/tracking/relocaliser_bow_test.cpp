// Issue 34 in the tracker: the place index (keyframe BoW vectors without excluded features, the
// database kept free of bad keyframes), ORBmatcher::SearchByBoW, and relocalisation over the
// whole map (backbone.relocalisation: bow) where the 10-recent rule cannot find the place.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "core/rng.h"
#include "features/orb_extractor.h"
#include "mapping/local_mapper.h"
#include "tracking/matcher.h"
#include "tracking/matcher_bow.h"
#include "tracking/place_index.h"
#include "tracking/real_frames.h"
#include "tracking/tracker.h"

using namespace dynref;

namespace {

// Frame 2 of fr1_desk with its image replaced by seeded blurred noise at 2 m: a view of no mapped place.
Frame NoiseFrame(const Sequence& seq, features::OrbExtractor& ex, uint64_t seed, int index) {
  Frame f = test::LoadRealFrame(seq, 2, ex, index);
  Rng rng(seed, "test.texture");
  cv::Mat noise(f.grey.size(), CV_8U);
  for (int y = 0; y < noise.rows; ++y)
    for (int x = 0; x < noise.cols; ++x) noise.at<uint8_t>(y, x) = static_cast<uint8_t>(rng.UniformInt(0, 255));
  cv::GaussianBlur(noise, noise, cv::Size(5, 5), 1.5);
  f.grey = noise;
  f.keys.clear();
  ex.Extract(noise, &f.keys, &f.descriptors);
  f.depth_m.setTo(2.0f);
  f.FinishFeatures(seq.camera);
  return f;
}

}  // namespace

TEST_CASE("place index: excluded features stay out of the vectors, bad keyframes leave the database") {
  const Sequence seq = test::Fr1Desk();
  features::OrbExtractor ex{features::OrbOptions{}};
  tracking::PlaceIndex index("default");
  Frame f = test::LoadRealFrame(seq, 0, ex);
  const tracking::PlaceBow all = index.Compute(f);
  REQUIRE_FALSE(all.bow.empty());
  place::BowVector bow_all;
  place::FeatureVector fv_all;
  index.vocabulary().Transform(f.descriptors, &bow_all, &fv_all, index.levels_up());
  CHECK(bow_all == all.bow);  // nothing excluded: the vocabulary's own transform
  CHECK(fv_all == all.features);
  for (int i = 0; i < static_cast<int>(f.N()); i += 2) f.Exclude(i, "test", "even");
  const tracking::PlaceBow odd = index.Compute(f);
  for (const auto& [node, list] : odd.features)
    for (uint32_t i : list) CHECK(i % 2 == 1);
  double sum = 0;
  for (const auto& [w, v] : odd.bow) sum += v;
  CHECK(sum == Approx(1.0));  // L1-normalised
  // Same vectors as the vocabulary's own transform of the kept rows.
  cv::Mat kept;
  for (int i = 1; i < static_cast<int>(f.N()); i += 2) kept.push_back(f.descriptors.row(i));
  place::BowVector direct;
  index.vocabulary().Transform(kept, &direct, nullptr, index.levels_up());
  CHECK(direct == odd.bow);
  // Database bookkeeping.
  Map map;
  for (int k = 0; k < 2; ++k) {
    auto kf = std::make_unique<KeyFrame>();
    kf->frame = test::LoadRealFrame(seq, k, ex);
    kf->map_point_ids.assign(kf->frame.N(), -1);
    index.Add(*map.AddKeyFrame(std::move(kf)));
  }
  CHECK(index.database().size() == 2);
  map.kf(0)->bad = true;
  index.EraseBad(map);
  CHECK(index.database().size() == 1);
  CHECK(index.Of(0) == nullptr);
  CHECK(index.Of(1) != nullptr);
}

TEST_CASE("SearchByBoW: a keyframe matched against its own frame gives the identity, one to one") {
  const Sequence seq = test::Fr1Desk();
  features::OrbExtractor ex{features::OrbOptions{}};
  tracking::PlaceIndex index("default");
  Map map;
  auto owned = std::make_unique<KeyFrame>();
  owned->frame = test::LoadRealFrame(seq, 0, ex);
  const int n = static_cast<int>(owned->frame.N());
  owned->map_point_ids.assign(n, -1);
  KeyFrame* kf = map.AddKeyFrame(std::move(owned));
  for (int i = 0; i < n; ++i) map.AddObservation(map.NewMapPoint(Eigen::Vector3d(0, 0, 1), kf->id, 0)->id, kf->id, i);
  index.Add(*kf);
  Frame cur = test::LoadRealFrame(seq, 0, ex);
  const tracking::PlaceBow cur_bow = index.Compute(cur);
  const int matched = tracking::SearchByBoW(*kf, *index.Of(kf->id), cur, cur_bow, map, 0.75f, true);
  int identity = 0;
  std::set<int64_t> used;
  for (int i = 0; i < n; ++i) {
    if (cur.map_point_ids[i] < 0) continue;
    identity += cur.map_point_ids[i] == kf->map_point_ids[i];
    CHECK(used.insert(cur.map_point_ids[i]).second);
  }
  CHECK(matched > n / 2);  // duplicates (distance 0 twice) fail the ratio test
  CHECK(identity == matched);
  // Brute force finds at least as many (it searches every pair).
  Frame cur2 = test::LoadRealFrame(seq, 0, ex);
  CHECK(tracking::SearchByBruteForce(*kf, cur2, map, 0.75f, true) >= matched);
}

TEST_CASE("relocalisation: bow finds a place older than the 10 most recent keyframes, recent does not") {
  const Sequence seq = test::Fr1Desk();
  for (const std::string rule : {"recent", "bow"}) {
    for (const bool bow_matching : {false, true}) {
      if (rule == "recent" && bow_matching) continue;
      features::OrbExtractor ex{features::OrbOptions{}};
      trace::TraceWriter trace{"", trace::Level::kOff, trace::RunHeader{}};
      Map map;
      tracking::TrackerOptions to;
      to.relocalisation = rule;
      to.bow_matching = bow_matching;
      tracking::Tracker tracker{seq.camera, map, to, trace};
      tracking::PlaceIndex index("default");
      tracker.SetPlaceIndex(&index);
      mapping::LocalMapper mapper{map, seq.camera, mapping::LocalMapperOptions{}, trace};
      Frame f0 = test::LoadRealFrame(seq, 0, ex);
      KeyFrame* kf = tracker.TryInitialise(f0);
      REQUIRE(kf != nullptr);
      mapper.ProcessKeyFrame(kf->id);
      index.AddAfterMapping(*kf, map);
      tracker.FinishFrame(f0, true);
      // Ten later keyframes of an unrelated (noise) place, without map points.
      for (int k = 0; k < 10; ++k) {
        auto owned = std::make_unique<KeyFrame>();
        owned->frame = NoiseFrame(seq, ex, 100 + k, 1);
        owned->map_point_ids.assign(owned->frame.N(), -1);
        index.Add(*map.AddKeyFrame(std::move(owned)));
      }
      Frame f1 = test::LoadRealFrame(seq, 1, ex);
      for (size_t i = 0; i < f1.N(); ++i) f1.Exclude(static_cast<int>(i), "test", "all");
      REQUIRE_FALSE(tracker.TrackInitial(f1));
      tracker.FinishFrame(f1, false);
      REQUIRE(tracker.state() == tracking::TrackState::kLost);
      Frame f3 = test::LoadRealFrame(seq, 3, ex);
      INFO("rule " << rule << " bow_matching " << bow_matching);
      CHECK(tracker.TrackInitial(f3) == (rule == "bow"));
    }
  }
}
