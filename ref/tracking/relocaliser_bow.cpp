// Relocalisation candidates and keyframe matching by vocabulary; see relocaliser_bow.h.
#include "tracking/relocaliser_bow.h"

#include <cmath>

#include "tracking/matcher.h"
#include "tracking/matcher_bow.h"

namespace dynref::tracking {

std::vector<int64_t> RelocalisationCandidates(const Frame& f, const Map& map, const TrackerOptions& options,
                                              PlaceIndex* place, trace::TraceWriter& trace, PlaceBow* frame_bow) {
  std::vector<int64_t> candidates;
  if (options.relocalisation == "bow" && place != nullptr) {
    place->EraseBad(map);
    *frame_bow = place->Compute(f);
    place::PlaceQueryReport report;
    const std::vector<place::KeyFrameId> found =
        place->database().DetectRelocalizationCandidates(frame_bow->bow, PlaceIndex::Covisible(map), &report);
    for (place::KeyFrameId id : found) {
      const KeyFrame* k = map.kf(static_cast<int64_t>(id));
      if (k != nullptr && !k->bad) candidates.push_back(static_cast<int64_t>(id));
    }
    trace.FrameCount("track.reloc", "bow_sharing", static_cast<int64_t>(report.sharing.size()));
    trace.FrameCount("track.reloc", "bow_scored", static_cast<int64_t>(report.scored.size()));
    trace.FrameCount("track.reloc", "bow_best_group_score_e6",
                     static_cast<int64_t>(std::llround(static_cast<double>(report.best_group_score) * 1e6)));
  } else {
    for (auto it = map.keyframes.rbegin(); it != map.keyframes.rend(); ++it) {
      if (it->second->bad) continue;
      candidates.push_back(it->first);
      if (static_cast<int>(candidates.size()) >= options.reloc_recent_keyframes) break;
    }
    if (place != nullptr && options.bow_matching) *frame_bow = place->Compute(f);
  }
  trace.FrameCount("track.reloc", "candidates", static_cast<int64_t>(candidates.size()));
  return candidates;
}

int MatchRelocalisationCandidate(const KeyFrame& kf, Frame& f, const Map& map, const TrackerOptions& options,
                                 const PlaceIndex* place, const PlaceBow& frame_bow) {
  const PlaceBow* kf_bow = place != nullptr && options.bow_matching ? place->Of(kf.id) : nullptr;
  if (kf_bow != nullptr) return SearchByBoW(kf, *kf_bow, f, frame_bow, map, 0.75f, true);
  return SearchByBruteForce(kf, f, map, 0.75f, true, options.mnn2, "match.mnn2.relocalisation");
}

int MatchReferenceKeyFrame(const KeyFrame& kf, Frame& f, const Map& map, const TrackerOptions& options,
                           const PlaceIndex* place) {
  const PlaceBow* kf_bow = place != nullptr && options.bow_matching ? place->Of(kf.id) : nullptr;
  if (kf_bow == nullptr) return SearchByBruteForce(kf, f, map, 0.7f, true, options.mnn2, "match.mnn2.reference");
  const PlaceBow frame_bow = place->Compute(f);
  return SearchByBoW(kf, *kf_bow, f, frame_bow, map, 0.7f, true);
}

}  // namespace dynref::tracking
