// Previous-frame correspondences of MGD-SLAM's temporal inheritance and short-term cue (seed 000
// Sec. 3.4, spec step 7 and E3): a current feature corresponds to the previous frame's feature
// that observed the same map point, else to the previous feature within match_radius_px whose
// descriptor is closest; either way only when the descriptors are similar: Hamming <=
// (1 - delta) 256 bits (delta = 0.6 read as a similarity: 102 bits, ORB-SLAM2's TH_HIGH = 100);
// float descriptors (issue 17): squared L2 of unit rows <= (1 - delta) 4.
#pragma once
#include <vector>

#include "map/frame.h"

namespace dynref::mgd {

enum class CorrespondenceSource { kNone = 0, kMapPoint = 1, kDescriptorWindow = 2 };

struct Correspondence {
  int prev_index = -1;
  CorrespondenceSource source = CorrespondenceSource::kNone;
  float hamming = -1;  // descriptor distance (Hamming bits for ORB; traced as input "hamming")
};

// One entry per current feature (excluded ones: none). Deterministic: ties keep the lowest index.
// threads (the run's --threads): features in chunks side by side, the same entries for any count.
std::vector<Correspondence> MatchPrevious(const Frame& cur, const Frame& prev, double delta, double radius_px,
                                          int threads = 1);

}  // namespace dynref::mgd
