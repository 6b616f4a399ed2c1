// Frame-to-frame line correspondence (issue 13 item 1, used by seed 000's line samples, issue 14).
// A current line takes the previous frame's line that observed the same map line; otherwise the
// previous line with the smallest LBD Hamming distance among those within the angle gate
// (spec 000 E14: tau_theta), whose midpoint lies within radius_px of the current infinite line
// (and vice versa), and whose distance is at most max_bits. Each previous line is used once
// (candidates in ascending (source, Hamming, current index, previous index) order).
#pragma once
#include <vector>

#include "map/structure.h"

namespace dynref::structure {

struct LineCorrespondence {
  int prev_index = -1;
  bool reversed = false;  // the previous segment runs e -> s relative to the current one
  int hamming = -1;
  int source = -1;        // 0 shared map line, 1 descriptor match
};

struct LineMatchGates {
  double angle_rad = 3.0 * 3.14159265358979323846 / 180.0;
  double radius_px = 15;
  int max_bits = 90;
};

std::vector<LineCorrespondence> MatchLinesToPrevious(const FrameStructure& cur, const FrameStructure& prev,
                                                     const LineMatchGates& gates);

// Whether prev's segment runs against cur's (sum of endpoint distances smaller when swapped).
bool SegmentReversed(const FrameLine& cur, const FrameLine& prev);

}  // namespace dynref::structure
