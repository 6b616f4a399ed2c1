// Local mapping (ORB-SLAM2 LocalMapping, sequential) on the real TUM fr1 frames, with a keyframe
// forced on every frame: triangulation creates points, local BA runs once the map has 3
// keyframes, map points stay consistent with their keyframes; and with the same view given again
// and again, redundant keyframes are culled (never the first).
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

struct Run {
  Sequence seq = OpenSequence(test::SourcePath("datasets/real/tum_fr1_desk_9frames"));
  features::OrbExtractor ex{features::OrbOptions{}};
  trace::TraceWriter trace{"", trace::Level::kOff, trace::RunHeader{}};
  Map map;
  tracking::Tracker tracker{seq.camera, map, tracking::TrackerOptions{}, trace};
  mapping::LocalMapper mapper{map, seq.camera, mapping::LocalMapperOptions{}, trace};
  int frames = 0;
  // Tracks image `image` of the sequence as the next frame and makes it a keyframe.
  mapping::LocalMapperStats KeyFrameOf(int image) {
    Frame f = test::LoadRealFrame(seq, image, ex, frames++);
    f.stamp = seq.frames[0].rgb_stamp + 0.03 * f.index;
    KeyFrame* kf = nullptr;
    if (f.index == 0) {
      kf = tracker.TryInitialise(f);
    } else {
      REQUIRE(tracker.TrackInitial(f));
      tracker.SearchLocalMap(f);
      REQUIRE(tracker.OptimizeFinal(f));
      kf = tracker.CreateNewKeyFrame(f);  // forced, whatever NeedNewKeyFrame says
    }
    REQUIRE(kf != nullptr);
    const mapping::LocalMapperStats s = mapper.ProcessKeyFrame(kf->id);
    tracker.FinishFrame(f, true);
    return s;
  }
};

}  // namespace

TEST_CASE("local mapper: the same view again and again: redundant keyframes are culled, never the first") {
  Run r;
  int culled = 0;
  for (int k = 0; k < 8; ++k) culled += r.KeyFrameOf(0).culled_keyframes;
  INFO("culled " << culled);
  CHECK(culled >= 2);
  CHECK_FALSE(r.map.kf(0)->bad);
  int live = 0;
  for (const auto& [id, kf] : r.map.keyframes) live += !kf->bad;
  CHECK(live == 8 - culled);
}

TEST_CASE("local mapper: triangulation, local BA and consistent map points on real frames") {
  const Sequence seq = OpenSequence(test::SourcePath("datasets/real/tum_fr1_desk_9frames"));
  features::OrbExtractor ex{features::OrbOptions{}};
  trace::TraceWriter trace{"", trace::Level::kOff, trace::RunHeader{}};
  Map map;
  tracking::Tracker tracker{seq.camera, map, tracking::TrackerOptions{}, trace};
  mapping::LocalMapper mapper{map, seq.camera, mapping::LocalMapperOptions{}, trace};
  int new_points = 0, culled_kfs = 0, triangulating_kfs = 0;
  for (int i = 0; i < 9; ++i) {
    Frame f = test::LoadRealFrame(seq, i, ex);
    KeyFrame* kf = nullptr;
    bool ok = true;
    if (i == 0) {
      kf = tracker.TryInitialise(f);
      REQUIRE(kf != nullptr);
    } else {
      ok = tracker.TrackInitial(f);
      REQUIRE(ok);
      tracker.SearchLocalMap(f);
      REQUIRE(tracker.OptimizeFinal(f));
      kf = tracker.CreateNewKeyFrame(f);  // a keyframe on every frame: redundancy to cull
    }
    const mapping::LocalMapperStats s = mapper.ProcessKeyFrame(kf->id);
    new_points += s.new_points;
    triangulating_kfs += s.new_points > 0;
    culled_kfs += s.culled_keyframes;
    tracker.FinishFrame(f, ok);
  }
  INFO("new points " << new_points << ", culled keyframes " << culled_kfs << ", BA calls " << mapper.ba_calls());
  CHECK(triangulating_kfs >= 1);  // RGB-D: most points come from depth, a few are triangulated
  CHECK(new_points > 0);
  CHECK(mapper.ba_calls() == 7);  // keyframes 2..8 (local BA needs more than 2 keyframes)
  REQUIRE(map.kf(0) != nullptr);
  CHECK_FALSE(map.kf(0)->bad);
  int checked = 0;
  for (const auto& [id, p] : map.points) {
    if (p->bad) {
      CHECK(p->observations.empty());
      continue;
    }
    if (p->first_kf == 0) continue;  // initial points come from depth, not triangulation
    // A triangulated point is seen by at least 2 live keyframes and lies in front of each.
    int live = 0;
    for (const auto& [kf_id, idx] : p->observations) {
      const KeyFrame* k = map.kf(kf_id);
      REQUIRE(k != nullptr);
      CHECK_FALSE(k->bad);
      CHECK((k->T_cw * p->X_w).z() > 0);
      CHECK(k->map_point_ids[idx] == id);
      ++live;
    }
    CHECK(live >= 1);
    ++checked;
  }
  CHECK(checked > 100);
}
