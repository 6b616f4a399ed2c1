// The tracker's steps one at a time on the bundled real TUM fr1_desk frames: reference-keyframe
// tracking, the motion model, the local-map search and the keyframe decision (ORB-SLAM2
// Tracking::TrackReferenceKeyFrame / TrackWithMotionModel / SearchLocalPoints / NeedNewKeyFrame).
#include <algorithm>
#include <catch2/catch.hpp>
#include <set>

#include "features/orb_extractor.h"
#include "io/sequence.h"
#include "mapping/local_mapper.h"
#include "tracking/real_frames.h"
#include "tracking/tracker.h"
#include "test_support.h"

using namespace dynref;

namespace {

struct Steps {
  Sequence seq = test::Fr1Desk();
  features::OrbExtractor extractor{features::OrbOptions{}};
  trace::TraceWriter trace{"", trace::Level::kOff, trace::RunHeader{}};
  Map map;
  tracking::Tracker tracker{seq.camera, map, tracking::TrackerOptions{}, trace};
  mapping::LocalMapper mapper{map, seq.camera, mapping::LocalMapperOptions{}, trace};

  // Image `image` as frame number `index`.
  Frame Load(int image, int index) { return test::LoadRealFrame(seq, image, extractor, index); }
  // Frame 0 (image 0) initialises the map.
  KeyFrame* Initialise() {
    Frame f0 = Load(0, 0);
    KeyFrame* kf = tracker.TryInitialise(f0);
    if (kf != nullptr) mapper.ProcessKeyFrame(kf->id);
    tracker.FinishFrame(f0, kf != nullptr);
    return kf;
  }
  bool TrackAll(Frame& f) {
    bool ok = tracker.TrackInitial(f);
    if (ok) {
      tracker.SearchLocalMap(f);
      ok = tracker.OptimizeFinal(f);
    }
    tracker.FinishFrame(f, ok);
    return ok;
  }
};

int Matched(const Frame& f) {
  int n = 0;
  for (size_t i = 0; i < f.N(); ++i) n += f.map_point_ids[i] >= 0 ? 1 : 0;
  return n;
}

}  // namespace

TEST_CASE("tracking reference keyframe: the keyframe's own image tracks to its pose") {
  Steps s;
  KeyFrame* kf = s.Initialise();
  REQUIRE(kf != nullptr);
  Frame f = s.Load(0, 1);  // no velocity yet: reference-keyframe tracking
  REQUIRE(s.tracker.TrackInitial(f));
  CHECK(Matched(f) > 300);
  CHECK(f.T_cw.translation().norm() < 0.002);
  CHECK(Eigen::AngleAxisd(f.T_cw.linear()).angle() < 0.002);
  // Every association points at a good map point the keyframe observes.
  for (size_t i = 0; i < f.N(); ++i)
    if (f.map_point_ids[i] >= 0) {
      const MapPoint* p = s.map.good_mp(f.map_point_ids[i]);
      REQUIRE(p != nullptr);
      CHECK(p->observations.count(kf->id) == 1);
    }
  CHECK(s.tracker.reference_kf() == kf);
}

TEST_CASE("tracking motion model: a still camera's velocity keeps the next frame at the same pose") {
  Steps s;
  REQUIRE(s.Initialise() != nullptr);
  Frame f1 = s.Load(0, 1);
  REQUIRE(s.TrackAll(f1));
  Frame f2 = s.Load(0, 2);  // a velocity exists now: the motion model predicts from frame 1
  REQUIRE(s.tracker.TrackInitial(f2));
  CHECK((f2.T_cw.translation() - f1.T_cw.translation()).norm() < 0.002);
  CHECK(Matched(f2) > 300);
  // A moving camera: the motion model carries frame 1 -> 2's motion into frame 3.
  Steps m;
  REQUIRE(m.Initialise() != nullptr);
  Frame g1 = m.Load(1, 1), g2 = m.Load(2, 2), g3 = m.Load(3, 3);
  REQUIRE(m.TrackAll(g1));
  REQUIRE(m.TrackAll(g2));
  REQUIRE(m.TrackAll(g3));
  CHECK(g3.T_cw.translation().norm() > g1.T_cw.translation().norm());
  CHECK((g3.T_cw.translation() - g2.T_cw.translation()).norm() < 0.1);
}

TEST_CASE("tracking local map: the search adds matches to unmatched features only, never excluded ones") {
  Steps s;
  REQUIRE(s.Initialise() != nullptr);
  Frame f = s.Load(1, 1);
  const int excluded = 50;
  for (int i = 0; i < excluded; ++i) f.Exclude(i, "test", "excluded");
  REQUIRE(s.tracker.TrackInitial(f));
  const std::vector<int64_t> before = f.map_point_ids;
  s.tracker.SearchLocalMap(f);
  CHECK(Matched(f) >= static_cast<int>(std::count_if(before.begin(), before.end(), [](int64_t id) { return id >= 0; })));
  for (size_t i = 0; i < f.N(); ++i)
    if (before[i] >= 0) CHECK(f.map_point_ids[i] == before[i]);  // earlier matches are kept
  for (int i = 0; i < excluded; ++i) CHECK(f.map_point_ids[static_cast<size_t>(i)] == -1);
  // Each point is matched at most once.
  std::set<int64_t> seen;
  for (int64_t id : f.map_point_ids)
    if (id >= 0) CHECK(seen.insert(id).second);
  CHECK(s.tracker.OptimizeFinal(f));
}

TEST_CASE("tracking keyframe decision: the keyframe's own view needs no keyframe, a full queue never gets one") {
  Steps s;
  REQUIRE(s.Initialise() != nullptr);
  Frame same = s.Load(0, 1);
  REQUIRE(s.tracker.TrackInitial(same));
  s.tracker.SearchLocalMap(same);
  REQUIRE(s.tracker.OptimizeFinal(same));
  CHECK_FALSE(s.tracker.NeedNewKeyFrame(same, true, 0, 3));  // as many matches as the keyframe has
  s.tracker.FinishFrame(same, true);
  // Far from the keyframe: fewer matches than 0.4 of the reference's (one keyframe in the map).
  bool wanted = false;
  for (int image = 2; image < 9 && !wanted; ++image) {
    Frame f = s.Load(image, image);
    bool ok = s.tracker.TrackInitial(f);
    if (ok) {
      s.tracker.SearchLocalMap(f);
      ok = s.tracker.OptimizeFinal(f);
    }
    if (!ok) break;
    wanted = s.tracker.NeedNewKeyFrame(f, true, 0, 3);
    if (wanted) {
      CHECK_FALSE(s.tracker.NeedNewKeyFrame(f, false, 3, 3));  // busy mapping with a full queue: never
      KeyFrame* k = s.tracker.CreateNewKeyFrame(f);
      CHECK(s.tracker.reference_kf() == k);
    }
    s.tracker.FinishFrame(f, ok);
  }
  CHECK(wanted);
}
