// ORB-SLAM2 KeyFrameDatabase (see keyframe_database.h for the rules and the one deviation).
#include "place/keyframe_database.h"

#include <algorithm>

namespace dynref::place {

void KeyFrameDatabase::Add(KeyFrameId id, const BowVector& bow) {
  Erase(id);
  for (const auto& [word, w] : bow) {
    std::vector<KeyFrameId>& list = inverted_[word];
    list.insert(std::lower_bound(list.begin(), list.end(), id), id);
  }
  bows_[id] = bow;
}

void KeyFrameDatabase::Erase(KeyFrameId id) {
  const auto it = bows_.find(id);
  if (it == bows_.end()) return;
  for (const auto& [word, w] : it->second) {
    auto inv = inverted_.find(word);
    if (inv == inverted_.end()) continue;
    std::vector<KeyFrameId>& list = inv->second;
    const auto pos = std::lower_bound(list.begin(), list.end(), id);
    if (pos != list.end() && *pos == id) list.erase(pos);
    if (list.empty()) inverted_.erase(inv);
  }
  bows_.erase(it);
}

void KeyFrameDatabase::Clear() {
  inverted_.clear();
  bows_.clear();
}

const std::vector<KeyFrameId>& KeyFrameDatabase::KeyFramesWithWord(WordId w) const {
  static const std::vector<KeyFrameId> kNone;
  const auto it = inverted_.find(w);
  return it == inverted_.end() ? kNone : it->second;
}

std::vector<KeyFrameId> KeyFrameDatabase::DetectLoopCandidates(KeyFrameId query, const BowVector& bow,
                                                               const std::set<KeyFrameId>& connected, float min_score,
                                                               const CovisibleFn& covisible,
                                                               PlaceQueryReport* report) const {
  std::set<KeyFrameId> excluded = connected;
  excluded.insert(query);
  return Detect(bow, excluded, true, min_score, covisible, report);
}

std::vector<KeyFrameId> KeyFrameDatabase::DetectRelocalizationCandidates(const BowVector& bow,
                                                                         const CovisibleFn& covisible,
                                                                         PlaceQueryReport* report) const {
  return Detect(bow, {}, false, 0.0f, covisible, report);
}

std::vector<KeyFrameId> KeyFrameDatabase::Detect(const BowVector& bow, const std::set<KeyFrameId>& excluded, bool loop,
                                                 float min_score, const CovisibleFn& covisible,
                                                 PlaceQueryReport* report) const {
  PlaceQueryReport local;
  PlaceQueryReport& rep = report != nullptr ? *report : local;
  rep = PlaceQueryReport{};
  // 1. Keyframes sharing words with the query, with the count (ascending id).
  std::map<KeyFrameId, int> shared;
  for (const auto& [word, w] : bow) {
    const auto it = inverted_.find(word);
    if (it == inverted_.end()) continue;
    for (KeyFrameId kf : it->second)
      if (!excluded.count(kf)) ++shared[kf];
  }
  if (shared.empty()) return {};
  for (const auto& [kf, n] : shared) {
    rep.sharing.push_back(kf);
    rep.max_shared_words = std::max(rep.max_shared_words, n);
  }
  // 2. Score those sharing enough words (ORB-SLAM2: int minCommonWords = maxCommonWords * 0.8f).
  rep.min_shared_words = static_cast<int>(static_cast<float>(rep.max_shared_words) * 0.8f);
  std::map<KeyFrameId, float> score_of;  // every keyframe scored in this query
  for (const auto& [kf, n] : shared) {
    if (n <= rep.min_shared_words) continue;
    const float s = static_cast<float>(vocabulary_->Score(bow, bows_.at(kf)));
    if (loop) {
      score_of[kf] = s;  // mLoopScore is set before the min_score test
      if (s < min_score) continue;
    } else {
      score_of[kf] = s;
    }
    rep.scored.push_back({kf, n, s, 0.0f, kf});
  }
  if (rep.scored.empty()) return {};
  // 3. Accumulate over covisibility groups.
  float best_acc = loop ? min_score : 0.0f;
  for (PlaceQueryReport::Scored& sc : rep.scored) {
    float best = sc.score, acc = sc.score;
    KeyFrameId best_kf = sc.id;
    for (KeyFrameId nb : covisible(sc.id, 10)) {
      const auto it = score_of.find(nb);
      if (it == score_of.end()) continue;
      acc += it->second;
      if (it->second > best) {
        best = it->second;
        best_kf = nb;
      }
    }
    sc.group_score = acc;
    sc.group_best = best_kf;
    if (acc > best_acc) best_acc = acc;
  }
  // 4. Keep the groups above 0.75 of the best, each keyframe once.
  rep.best_group_score = best_acc;
  rep.min_group_score = 0.75f * best_acc;
  std::set<KeyFrameId> added;
  for (const PlaceQueryReport::Scored& sc : rep.scored)
    if (sc.group_score > rep.min_group_score && added.insert(sc.group_best).second)
      rep.candidates.push_back(sc.group_best);
  return rep.candidates;
}

}  // namespace dynref::place
