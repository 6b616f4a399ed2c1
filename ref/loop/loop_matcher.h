// ORBmatcher searches of ORB-SLAM2's loop closing (Mur-Artal & Tardos, T-RO 2017, Sec. V-B/C) on
// dynref keyframes, deterministic (features in ascending index, nodes in ascending id):
//  - SearchByBoWKeyFrames = SearchByBoW(KeyFrame*, KeyFrame*, vector<MapPoint*>&): features of
//    the same vocabulary node that both have a good map point; best < TH_LOW (strict, as ORB-SLAM2
//    there), best < ratio * second best, each keyframe-2 feature used once, rotation histogram;
//  - SearchByProjectionPose = SearchByProjection(KeyFrame*, Scw, vpPoints, vpMatched, th) with a
//    rigid T_cw: points in front, inside the image, within the scale-invariance distances and a
//    viewing angle below 60 deg, keypoints of the predicted level or one below within th * scale,
//    best distance <= TH_LOW, features already matched skipped;
//  - FusePose = Fuse(KeyFrame*, Scw, vpPoints, th, vpReplacePoint): the same projection test
//    (levels predicted-1 .. predicted), best <= TH_LOW; the keyframe's own point at that feature is
//    to be replaced by the projected one, or the projected point gains the observation.
// Excluded features (a method's dynamic features) never take part.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "map/map.h"
#include "tracking/place_index.h"

namespace dynref::loop {

// Per feature of kf1: the map point of the matched kf2 feature, or -1.
std::vector<int64_t> SearchByBoWKeyFrames(const KeyFrame& kf1, const tracking::PlaceBow& bow1, const KeyFrame& kf2,
                                          const tracking::PlaceBow& bow2, const Map& map, float ratio);

// Adds matches to `matched` (per feature of kf, -1 = none) for `points` not yet in it; returns
// how many were added.
int SearchByProjectionPose(const KeyFrame& kf, const SE3& T_cw, const std::vector<int64_t>& points, const Map& map,
                           float th, std::vector<int64_t>* matched);

// Fusion of `points` into kf seen from T_cw: (feature, point) pairs to add (the feature has no
// point) and (kf's point, projected point) pairs to replace, both in the order of `points`.
struct FuseResult {
  std::vector<std::pair<int, int64_t>> add;
  std::vector<std::pair<int64_t, int64_t>> replace;  // (kf's point, by)
};
FuseResult FusePose(const KeyFrame& kf, const SE3& T_cw, const std::vector<int64_t>& points, const Map& map, float th);

}  // namespace dynref::loop
