// ORB-SLAM2 LoopClosing::DetectLoop (loop/loop_detector.h) on planted keyframes: ten keyframes of
// an unrelated (noise) place after a keyframe of the fr1_desk clip, then desk keyframes again,
// covisible with each other and with the last noise keyframe but not with the first one. The
// first keyframe is a candidate from the first revisit on, its group's consistency grows by one
// per keyframe, and it is accepted on the third consecutive detection (consistency 3).
#include <catch2/catch.hpp>
#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/rng.h"
#include "features/orb_extractor.h"
#include "loop/loop_detector.h"
#include "tracking/real_frames.h"

using namespace dynref;

namespace {

KeyFrame* AddKeyFrame(Map& map, tracking::PlaceIndex& index, Frame f) {
  auto owned = std::make_unique<KeyFrame>();
  owned->frame = std::move(f);
  owned->map_point_ids.assign(owned->frame.N(), -1);
  KeyFrame* kf = map.AddKeyFrame(std::move(owned));
  index.Add(*kf);
  return kf;
}

Frame Noise(const Frame& like, features::OrbExtractor& ex, uint64_t seed) {
  Frame f = like;
  Rng rng(seed, "test.texture");
  cv::Mat noise(f.grey.size(), CV_8U);
  for (int y = 0; y < noise.rows; ++y)
    for (int x = 0; x < noise.cols; ++x) noise.at<uint8_t>(y, x) = static_cast<uint8_t>(rng.UniformInt(0, 255));
  cv::GaussianBlur(noise, noise, cv::Size(5, 5), 1.5);
  f.keys.clear();
  ex.Extract(noise, &f.keys, &f.descriptors);
  f.FinishFeatures(*like.camera);
  return f;
}

void Connect(KeyFrame& a, KeyFrame& b) {
  a.connections[b.id] = 20;
  b.connections[a.id] = 20;
  for (KeyFrame* k : {&a, &b}) {
    k->ordered_covisibles.clear();
    for (const auto& [id, w] : k->connections) k->ordered_covisibles.push_back(id);
  }
}

}  // namespace

TEST_CASE("loop detector: a revisited place becomes a loop after three consistent detections") {
  const Sequence seq = test::Fr1Desk();
  features::OrbExtractor ex{features::OrbOptions{}};
  tracking::PlaceIndex index("default");
  Map map;
  AddKeyFrame(map, index, test::LoadRealFrame(seq, 0, ex));
  const Frame like = test::LoadRealFrame(seq, 8, ex);
  for (int k = 1; k <= 10; ++k) AddKeyFrame(map, index, Noise(like, ex, 200 + k));
  loop::LoopDetector detector{loop::LoopDetectorOptions{}};
  // Keyframe 10 (< 0 + 10 keyframes since the last loop) is skipped.
  CHECK(detector.Detect(*map.kf(9), map, index).skipped);
  std::vector<KeyFrame*> revisit;
  std::vector<int> consistency;
  std::vector<bool> accepted;
  for (int image : {1, 2, 3, 4}) {
    KeyFrame* kf = AddKeyFrame(map, index, test::LoadRealFrame(seq, image, ex));
    Connect(*kf, *map.kf(10));
    for (KeyFrame* prev : revisit) Connect(*kf, *prev);
    revisit.push_back(kf);
    const loop::LoopDetection d = detector.Detect(*kf, map, index);
    REQUIRE_FALSE(d.skipped);
    CHECK(d.min_score < 0.2f);  // the noise keyframe's score
    const auto it = std::find_if(d.candidates.begin(), d.candidates.end(), [](const loop::LoopCandidate& c) { return c.kf == 0; });
    REQUIRE(it != d.candidates.end());
    CHECK(it->score >= d.min_score);
    consistency.push_back(it->consistency);
    accepted.push_back(it->accepted);
    INFO("reason " << it->reason);
    CHECK(it->reason == (it->accepted ? "consistent" : it->consistency > 0 ? "not-consistent-enough" : "new-group"));
  }
  CHECK(consistency == std::vector<int>{0, 1, 2, 3});
  CHECK(accepted == std::vector<bool>{false, false, false, true});
  // Deterministic: the same calls on a fresh detector give the same candidates.
  loop::LoopDetector again{loop::LoopDetectorOptions{}};
  const loop::LoopDetection a = again.Detect(*revisit[0], map, index);
  const loop::LoopDetection b = loop::LoopDetector{loop::LoopDetectorOptions{}}.Detect(*revisit[0], map, index);
  REQUIRE(a.candidates.size() == b.candidates.size());
  for (size_t i = 0; i < a.candidates.size(); ++i) CHECK(a.candidates[i].kf == b.candidates[i].kf);
}

TEST_CASE("loop detector: min_score comes from the covisibles of weight >= 15, not from every connection") {
  // ORB-SLAM2 DetectLoop takes minScore over GetVectorCovisibleKeyFrames (weight >= 15); a keyframe
  // sharing a few points (here 3, a noise image) is excluded from the candidates but sets no bar.
  const Sequence seq = test::Fr1Desk();
  features::OrbExtractor ex{features::OrbOptions{}};
  tracking::PlaceIndex index("default");
  Map map;
  KeyFrame* desk = AddKeyFrame(map, index, test::LoadRealFrame(seq, 0, ex));
  KeyFrame* noise = AddKeyFrame(map, index, Noise(test::LoadRealFrame(seq, 8, ex), ex, 201));
  KeyFrame* kf = AddKeyFrame(map, index, test::LoadRealFrame(seq, 1, ex));
  Connect(*kf, *desk);
  kf->connections[noise->id] = 3;  // GetConnectedKeyFrames only
  noise->connections[kf->id] = 3;
  loop::LoopDetectorOptions o;
  o.min_keyframes_since_loop = 0;
  const loop::LoopDetection d = loop::LoopDetector{o}.Detect(*kf, map, index);
  REQUIRE_FALSE(d.skipped);
  const float desk_score = static_cast<float>(index.vocabulary().Score(index.Of(kf->id)->bow, index.Of(desk->id)->bow));
  const float noise_score = static_cast<float>(index.vocabulary().Score(index.Of(kf->id)->bow, index.Of(noise->id)->bow));
  REQUIRE(noise_score < desk_score);
  CHECK(d.min_score == desk_score);
  CHECK(d.candidates.empty());  // both keyframes are connected: never loop candidates
}

TEST_CASE("loop detector: options are checked") {
  loop::LoopDetectorOptions o;
  o.consistency = 0;
  CHECK_THROWS_AS(loop::LoopDetector{o}, InputError);
}
