// Tracker on real Kinect frames (TUM fr1_desk, 9 frames): initialisation, reference-keyframe
// and motion-model tracking, exclusion honoured, relocalisation after a lost frame.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "features/orb_extractor.h"
#include "io/sequence.h"
#include "mapping/local_mapper.h"
#include "tracking/real_frames.h"
#include "tracking/tracker.h"
#include "test_support.h"

using namespace dynref;

namespace {

struct Fixture {
  Sequence seq = OpenSequence(test::SourcePath("datasets/real/tum_fr1_desk_9frames"));
  features::OrbExtractor extractor{features::OrbOptions{}};
  trace::TraceWriter trace{"", trace::Level::kOff, trace::RunHeader{}};
  Map map;
  tracking::Tracker tracker{seq.camera, map, tracking::TrackerOptions{}, trace};
  mapping::LocalMapper mapper{map, seq.camera, mapping::LocalMapperOptions{}, trace};

  Frame Load(int i) { return test::LoadRealFrame(seq, i, extractor); }
  bool Track(Frame& f) {
    bool ok = tracker.TrackInitial(f);
    if (ok) {
      tracker.SearchLocalMap(f);
      ok = tracker.OptimizeFinal(f);
    }
    if (ok && tracker.NeedNewKeyFrame(f)) mapper.ProcessKeyFrame(tracker.CreateNewKeyFrame(f)->id);
    tracker.FinishFrame(f, ok);
    return ok;
  }
};

}  // namespace

TEST_CASE("tracking: real frames track, exclusion is honoured, relocalisation recovers") {
  Fixture fx;
  REQUIRE(fx.seq.camera.HasDistortion());
  Frame f0 = fx.Load(0);
  KeyFrame* kf = fx.tracker.TryInitialise(f0);
  REQUIRE(kf != nullptr);
  CHECK(fx.map.points.size() > 500);
  fx.mapper.ProcessKeyFrame(kf->id);
  fx.tracker.FinishFrame(f0, true);

  Frame f1 = fx.Load(1);
  REQUIRE(fx.Track(f1));  // reference keyframe (no velocity yet)
  CHECK(fx.tracker.matches_inliers() >= 100);
  Frame f2 = fx.Load(2);
  REQUIRE(fx.Track(f2));  // motion model
  // Frame-to-frame motion is small and the pose moved away from identity.
  CHECK(f2.T_cw.translation().norm() > 0.005);
  CHECK(f2.T_cw.translation().norm() < 0.2);

  // Every feature excluded: no match can be made, the frame is lost.
  Frame f3 = fx.Load(3);
  for (size_t i = 0; i < f3.N(); ++i) f3.Exclude(static_cast<int>(i), "test", "all");
  CHECK_FALSE(fx.Track(f3));
  CHECK(fx.tracker.state() == tracking::TrackState::kLost);
  for (size_t i = 0; i < f3.N(); ++i) CHECK(f3.map_point_ids[i] == -1);

  // Next frame: relocalisation against recent keyframes (seeded PnP RANSAC).
  Frame f4 = fx.Load(4);
  CHECK(fx.Track(f4));
  CHECK(fx.tracker.state() == tracking::TrackState::kOk);
  const auto& rec = fx.tracker.records();
  REQUIRE(rec.size() == 5);
  CHECK(rec[3].lost);
  CHECK_FALSE(rec[4].lost);
}

TEST_CASE("tracking: a busy local mapper restricts keyframes as ORB-SLAM2's NeedNewKeyFrame") {
  Fixture fx;
  Frame f0 = fx.Load(0);
  KeyFrame* kf = fx.tracker.TryInitialise(f0);
  REQUIRE(kf != nullptr);
  fx.mapper.ProcessKeyFrame(kf->id);
  fx.tracker.FinishFrame(f0, true);
  int wanted_when_idle = 0;
  for (int i = 1; i < 9; ++i) {
    Frame f = fx.Load(i);
    bool ok = fx.tracker.TrackInitial(f);
    if (ok) {
      fx.tracker.SearchLocalMap(f);
      ok = fx.tracker.OptimizeFinal(f);
    }
    if (!ok) break;
    const bool idle = fx.tracker.NeedNewKeyFrame(f, true, 0, 3);
    const bool busy = fx.tracker.NeedNewKeyFrame(f, false, 0, 3);
    CHECK_FALSE(fx.tracker.NeedNewKeyFrame(f, false, 3, 3));  // RGB-D: queue of 3 is full
    CHECK((!busy || idle));  // busy mapping never allows more than idle mapping
    wanted_when_idle += idle ? 1 : 0;
    if (idle) fx.mapper.ProcessKeyFrame(fx.tracker.CreateNewKeyFrame(f)->id);
    fx.tracker.FinishFrame(f, ok);
  }
  CHECK(wanted_when_idle > 0);
}
