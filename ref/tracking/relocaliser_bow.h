// Relocalisation candidates and keyframe-to-frame matching (issue 34). ORB-SLAM2
// Tracking::Relocalization asks the keyframe database for candidates over the whole map
// (KeyFrameDatabase::DetectRelocalizationCandidates) and matches each by vocabulary node
// (ORBmatcher::SearchByBoW, ratio 0.75, orientation check); dynref keeps its earlier rule as a
// switch (backbone.relocalisation):
//   recent: the reloc_recent_keyframes most recent good keyframes, newest first (no vocabulary);
//   bow:    the database's candidates, in the database's order (ascending id of the scored
//           keyframe), bad keyframes skipped.
// Matching: SearchByBoW when backbone.bow_matching is true, else brute force (matcher.h) as before.
// Trace (FrameCount, stage track.reloc): candidates; per tried candidate candidate_kf,
// candidate_matches, candidate_pnp_inliers and candidate_inliers (-1 = not reached;
// relocalise.cpp); with bow also bow_sharing (keyframes sharing a word), bow_scored and
// bow_best_group_score_e6 (best group score x 1e6, rounded).
#pragma once
#include <cstdint>
#include <vector>

#include "map/frame.h"
#include "map/map.h"
#include "trace/trace_writer.h"
#include "tracking/place_index.h"
#include "tracking/tracker.h"

namespace dynref::tracking {

// The keyframes relocalisation tries, in order. `place` may be nullptr only for "recent".
// `frame_bow` receives the frame's vectors when a vocabulary is used.
std::vector<int64_t> RelocalisationCandidates(const Frame& f, const Map& map, const TrackerOptions& options,
                                              PlaceIndex* place, trace::TraceWriter& trace, PlaceBow* frame_bow);

// Keyframe-to-frame matches of one candidate (ratio 0.75, orientation check, as ORB-SLAM2).
int MatchRelocalisationCandidate(const KeyFrame& kf, Frame& f, const Map& map, const TrackerOptions& options,
                                 const PlaceIndex* place, const PlaceBow& frame_bow);

// Reference-keyframe tracking's matches (ratio 0.7): SearchByBoW when options.bow_matching and a
// place index holds the keyframe, else brute force / MNN2 (matcher.h).
int MatchReferenceKeyFrame(const KeyFrame& kf, Frame& f, const Map& map, const TrackerOptions& options,
                           const PlaceIndex* place);

}  // namespace dynref::tracking
