// ORB-SLAM2 LoopClosing::DetectLoop; see loop_detector.h.
#include "loop/loop_detector.h"

#include <algorithm>

#include "core/error.h"

namespace dynref::loop {

void LoopDetectorOptions::Check() const {
  if (min_keyframes_since_loop < 0)
    throw InputError("loop options", "min_keyframes_since_loop must be >= 0");
  if (consistency < 1) throw InputError("loop options", "consistency must be >= 1");
}

LoopDetector::LoopDetector(const LoopDetectorOptions& options) : options_(options) { options_.Check(); }

LoopDetection LoopDetector::Detect(const KeyFrame& kf, const Map& map, const tracking::PlaceIndex& place) {
  LoopDetection out;
  if (kf.id < last_loop_kf_ + options_.min_keyframes_since_loop) {
    out.skipped = true;
    return out;
  }
  const tracking::PlaceBow* own = place.Of(kf.id);
  if (own == nullptr) {
    out.skipped = true;
    return out;
  }
  // Step 2: the lowest score among the covisible keyframes, GetVectorCovisibleKeyFrames (weight
  // >= 15, kf.ordered_covisibles); the candidates exclude every connected keyframe,
  // GetConnectedKeyFrames (kf.connections, any weight).
  std::set<place::KeyFrameId> connected;
  for (const auto& [c, weight] : kf.connections) connected.insert(static_cast<place::KeyFrameId>(c));
  for (int64_t c : kf.ordered_covisibles) {
    const KeyFrame* k = map.kf(c);
    if (k == nullptr || k->bad) continue;
    const tracking::PlaceBow* b = place.Of(c);
    if (b == nullptr) continue;
    out.min_score = std::min(out.min_score, static_cast<float>(place.vocabulary().Score(own->bow, b->bow)));
  }
  // Step 3.
  const std::vector<place::KeyFrameId> found = place.database().DetectLoopCandidates(
      static_cast<place::KeyFrameId>(kf.id), own->bow, connected, out.min_score, tracking::PlaceIndex::Covisible(map),
      &out.query);
  std::vector<std::pair<std::set<int64_t>, int>> current;
  if (found.empty()) {
    groups_.clear();
    return out;
  }
  // Step 4.
  std::vector<bool> carried(groups_.size(), false);
  for (place::KeyFrameId id : found) {
    LoopCandidate c;
    c.kf = static_cast<int64_t>(id);
    for (const place::PlaceQueryReport::Scored& s : out.query.scored)
      if (s.id == id) c.score = s.score;
    const KeyFrame* cand = map.kf(c.kf);
    std::set<int64_t> group;
    group.insert(c.kf);
    if (cand != nullptr)
      for (const auto& [other, w] : cand->connections) group.insert(other);
    bool some_group = false;
    for (size_t g = 0; g < groups_.size(); ++g) {
      const std::set<int64_t>& previous = groups_[g].first;
      const bool shares = std::any_of(group.begin(), group.end(), [&](int64_t m) { return previous.count(m) != 0; });
      if (!shares) continue;
      some_group = true;
      const int consistency = groups_[g].second + 1;
      c.consistency = std::max(c.consistency, consistency);
      if (!carried[g]) {
        current.emplace_back(group, consistency);
        carried[g] = true;
      }
      if (consistency >= options_.consistency && !c.accepted) {
        c.accepted = true;
        out.accepted.push_back(c.kf);
      }
    }
    if (!some_group) current.emplace_back(group, 0);
    c.reason = c.accepted ? "consistent" : some_group ? "not-consistent-enough" : "new-group";
    out.candidates.push_back(c);
  }
  groups_ = std::move(current);
  return out;
}

}  // namespace dynref::loop
