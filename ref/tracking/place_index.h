// The backbone's place recognition state (issue 34): the vocabulary, every keyframe's BowVector
// and FeatureVector (ORB-SLAM2 KeyFrame::ComputeBoW) and the keyframe database
// (place::KeyFrameDatabase, ORB-SLAM2 KeyFrameDatabase). One per run, owned by the frame loop;
// the tracker (relocalisation, optional SearchByBoW) and loop closing query it.
//
// Keyframes are added when they are created (map initialisation, CreateNewKeyFrame) and erased
// when they are bad: ORB-SLAM2 erases a keyframe from the database inside KeyFrame::SetBadFlag;
// here EraseBad runs before every query and after local mapping, which gives the same query
// results without a hook in the map (keyframe culling only happens in local mapping).
//
// Features a method excluded (Frame::Exclude: a dynamic feature) are left out of the BowVector and
// FeatureVector, as the dynamic-SLAM systems built on ORB-SLAM2 remove them before ComputeBoW.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "map/map.h"
#include "place/keyframe_database.h"
#include "place/vocabulary.h"

namespace dynref::tracking {

struct PlaceBow {
  place::BowVector bow;
  place::FeatureVector features;  // node (level 2 of the tree) -> keypoint indices, ascending
};

class PlaceIndex {
 public:
  // `vocabulary`: "default" (place::Vocabulary::Default()) or a file (dynref format or ORB-SLAM2's
  // ORBvoc.txt). InputError for a bad file.
  explicit PlaceIndex(const std::string& vocabulary);
  PlaceIndex(const PlaceIndex&) = delete;
  PlaceIndex& operator=(const PlaceIndex&) = delete;

  const place::Vocabulary& vocabulary() const { return *vocabulary_; }
  const place::KeyFrameDatabase& database() const { return database_; }
  // The FeatureVector level: ORB-SLAM2 transform(..., 4) with ORBvoc.txt's L = 6, i.e. level 2.
  int levels_up() const { return levels_up_; }

  // ORB-SLAM2 Frame::ComputeBoW over the frame's non-excluded features.
  PlaceBow Compute(const Frame& f) const;
  // ComputeBoW of a new keyframe and KeyFrameDatabase::add.
  void Add(const KeyFrame& kf);
  // Erases keyframes that are bad in `map` (KeyFrameDatabase::erase from SetBadFlag).
  void EraseBad(const Map& map);
  // After a keyframe's local mapping: EraseBad (keyframe culling), then Add unless kf is bad.
  void AddAfterMapping(const KeyFrame& kf, const Map& map);
  // The keyframe's vectors (nullptr when it was never added or is erased).
  const PlaceBow* Of(int64_t kf_id) const;
  // Best covisibles of a keyframe of `map` for the database's group scores.
  static place::CovisibleFn Covisible(const Map& map);

 private:
  std::unique_ptr<place::Vocabulary> owned_;  // loaded from a file
  const place::Vocabulary* vocabulary_ = nullptr;
  place::KeyFrameDatabase database_;
  int levels_up_ = 0;
  std::map<int64_t, PlaceBow> keyframes_;
};

}  // namespace dynref::tracking
