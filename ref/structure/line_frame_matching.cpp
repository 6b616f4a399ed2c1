#include "structure/line_frame_matching.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "features/lines.h"
#include "features/orb_extractor.h"

namespace dynref::structure {

bool SegmentReversed(const FrameLine& cur, const FrameLine& prev) {
  const double same = (cur.s - prev.s).norm() + (cur.e - prev.e).norm();
  const double swapped = (cur.s - prev.e).norm() + (cur.e - prev.s).norm();
  return swapped < same;
}

std::vector<LineCorrespondence> MatchLinesToPrevious(const FrameStructure& cur, const FrameStructure& prev,
                                                     const LineMatchGates& gates) {
  std::vector<LineCorrespondence> out(cur.lines.size());
  const bool have_desc = cur.line_descriptors.rows == static_cast<int>(cur.lines.size()) &&
                         prev.line_descriptors.rows == static_cast<int>(prev.lines.size());
  // (source, hamming, current, previous)
  std::vector<std::tuple<int, int, int, int>> cand;
  for (size_t i = 0; i < cur.lines.size(); ++i) {
    const FrameLine& C = cur.lines[i];
    if (C.l.head<2>().squaredNorm() == 0) continue;
    const int64_t ml = i < cur.map_line_ids.size() ? cur.map_line_ids[i] : -1;
    const Eigen::Vector2d cm = 0.5 * (C.s + C.e);
    for (size_t j = 0; j < prev.lines.size(); ++j) {
      const FrameLine& P = prev.lines[j];
      if (P.l.head<2>().squaredNorm() == 0) continue;
      const auto hamming = [&] {
        return have_desc ? features::DescriptorDistance(cur.line_descriptors.row(static_cast<int>(i)),
                                                        prev.line_descriptors.row(static_cast<int>(j)))
                         : -1;
      };
      if (ml >= 0 && j < prev.map_line_ids.size() && prev.map_line_ids[j] == ml) {  // same map line
        cand.emplace_back(0, std::max(hamming(), 0), static_cast<int>(i), static_cast<int>(j));
        continue;
      }
      // Geometric gates first (cheap), the descriptor distance only for pairs that pass them.
      if (!have_desc || features::LineAngleDiff(C.angle, P.angle) >= gates.angle_rad) continue;
      const Eigen::Vector2d pm = 0.5 * (P.s + P.e);
      if (std::fabs(C.l.dot(Eigen::Vector3d(pm.x(), pm.y(), 1))) > gates.radius_px ||
          std::fabs(P.l.dot(Eigen::Vector3d(cm.x(), cm.y(), 1))) > gates.radius_px)
        continue;
      const int ham = hamming();
      if (ham > gates.max_bits) continue;
      cand.emplace_back(1, ham, static_cast<int>(i), static_cast<int>(j));
    }
  }
  std::stable_sort(cand.begin(), cand.end());
  std::vector<uint8_t> used(prev.lines.size(), 0);
  for (const auto& [source, ham, i, j] : cand) {
    LineCorrespondence& c = out[static_cast<size_t>(i)];
    if (c.prev_index >= 0 || used[static_cast<size_t>(j)]) continue;
    used[static_cast<size_t>(j)] = 1;
    c.prev_index = j;
    c.source = source;
    c.hamming = ham;
    c.reversed = SegmentReversed(cur.lines[static_cast<size_t>(i)], prev.lines[static_cast<size_t>(j)]);
  }
  return out;
}

}  // namespace dynref::structure
