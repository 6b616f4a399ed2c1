// ORB-SLAM2's KeyFrameDatabase (src/KeyFrameDatabase.cc, Mur-Artal & Tardos 2017; place
// recognition of Mur-Artal & Tardos, "Fast relocalisation and loop closing in keyframe-based
// SLAM", ICRA 2014): an inverted file from each word to the keyframes whose BowVector holds it,
// and the two candidate searches over the whole map.
//
// Generic over keyframe ids: it stores ids and BowVectors only; the covisibility graph is asked
// through a callback (KeyFrame::GetBestCovisibilityKeyFrames(10) in ORB-SLAM2), so this room does
// not depend on ref/map.
//
// Both searches, as ORB-SLAM2:
//  1. keyframes sharing at least one word with the query (DetectLoopCandidates: minus the query's
//     connected keyframes), with their count of shared words;
//  2. only those sharing more than int(0.8f * max shared) words are scored: s = vocabulary score
//     (ORB-SLAM2 keeps it as float); loop candidates also need s >= min_score;
//  3. each scored keyframe's group = itself + its best 10 covisible keyframes that were scored in
//     this query; group score = sum of their s (float), group best = the member with the highest s;
//  4. return each group best whose group score > 0.75f * best group score (loop: best starts at
//     min_score, relocalisation at 0), each keyframe once.
// Determinism: ORB-SLAM2 visits keyframes in inverted-file order (insertion order, pointers);
// here step 1 collects keyframes in ascending id, steps 2-4 visit them in ascending id, so the
// result is ordered by the id of the group's scored keyframe. One deviation, on purpose: in
// relocalisation ORB-SLAM2 adds a neighbour's mRelocScore whenever the neighbour shares a word,
// also when it was not scored in this query (its score is then left over from an earlier query);
// here only neighbours scored in this query count (as ORB-SLAM2's DetectLoopCandidates does).
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include "place/bow.h"
#include "place/vocabulary.h"

namespace dynref::place {

using KeyFrameId = uint64_t;

// Best covisible keyframes of `kf`, at most `n`, best first (KeyFrame::GetBestCovisibilityKeyFrames).
using CovisibleFn = std::function<std::vector<KeyFrameId>(KeyFrameId kf, int n)>;

// What a search saw (for traces and tests).
struct PlaceQueryReport {
  struct Scored {
    KeyFrameId id = 0;
    int shared_words = 0;
    float score = 0;        // vocabulary score with the query
    float group_score = 0;  // accumulated over the covisibility group (0 when not grouped)
    KeyFrameId group_best = 0;
  };
  int max_shared_words = 0;
  int min_shared_words = 0;            // int(0.8f * max): scored when shared > this
  std::vector<KeyFrameId> sharing;     // step 1, ascending id
  std::vector<Scored> scored;          // step 2 (loop: only s >= min_score), ascending id
  float best_group_score = 0;
  float min_group_score = 0;           // 0.75f * best_group_score
  std::vector<KeyFrameId> candidates;  // the result
};

class KeyFrameDatabase {
 public:
  // The vocabulary (only its scoring is used) must outlive the database.
  explicit KeyFrameDatabase(const Vocabulary& vocabulary) : vocabulary_(&vocabulary) {}

  // KeyFrameDatabase::add / erase / clear. Adding an id twice replaces its vector.
  void Add(KeyFrameId id, const BowVector& bow);
  void Erase(KeyFrameId id);
  void Clear();
  size_t size() const { return bows_.size(); }
  bool Contains(KeyFrameId id) const { return bows_.count(id) != 0; }
  // Keyframes holding word w, ascending id.
  const std::vector<KeyFrameId>& KeyFramesWithWord(WordId w) const;

  // LoopClosing::DetectLoop's search: the query keyframe (excluded from its own candidates) with
  // its BowVector, its connected keyframes (excluded), the lowest score of its covisible
  // keyframes (min_score).
  std::vector<KeyFrameId> DetectLoopCandidates(KeyFrameId query, const BowVector& bow,
                                               const std::set<KeyFrameId>& connected, float min_score,
                                               const CovisibleFn& covisible, PlaceQueryReport* report = nullptr) const;
  // Tracking::Relocalization's search for a frame's BowVector over the whole map.
  std::vector<KeyFrameId> DetectRelocalizationCandidates(const BowVector& bow, const CovisibleFn& covisible,
                                                         PlaceQueryReport* report = nullptr) const;

 private:
  std::vector<KeyFrameId> Detect(const BowVector& bow, const std::set<KeyFrameId>& excluded, bool loop,
                                 float min_score, const CovisibleFn& covisible, PlaceQueryReport* report) const;

  const Vocabulary* vocabulary_;
  std::map<WordId, std::vector<KeyFrameId>> inverted_;  // word -> keyframes, ascending id
  std::map<KeyFrameId, BowVector> bows_;
};

}  // namespace dynref::place
