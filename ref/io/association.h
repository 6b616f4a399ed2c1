// Timestamp association of two stamp lists (ascending), reproducing the two public tools.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace dynref {

struct StampMatch {
  size_t first = 0;   // index into the first list
  size_t second = 0;  // index into the second list
};

enum class AssociationKind {
  kTum,  // TUM associate.py: greedy one-to-one
  kEvo,  // evo associate_trajectories: nearest neighbour, not one-to-one
};
const char* AssociationKindName(AssociationKind kind);  // "tum" / "evo"

// TUM rgbd_benchmark_tools associate.py `associate(first, second, offset, max_difference)`:
// every candidate (a, b) with |a - (b + offset)| < max_difference (strict) is sorted by
// (difference, a, b) ascending and accepted greedily when neither a nor b is taken yet.
// Result sorted by first stamp. Stamps must be strictly increasing (they are dict keys there).
std::vector<StampMatch> AssociateTum(const std::vector<double>& first,
                                     const std::vector<double>& second, double max_difference_s,
                                     double offset_s = 0.0);

// evo core/sync.py associate_trajectories(traj_1, traj_2, max_diff, offset_2): the list with
// fewer poses (the "short" one) is walked in order and each of its stamps is matched to the nearest stamp of the other list (argmin, first
// index on ties) when |diff| <= max_diff (inclusive). The same stamp of the longer list may be
// used by several pairs. evo: first_longer = n_first >= n_second, so on equal counts the second
// list is the walked one. Result sorted by the walked list's index; indices refer to first/second.
std::vector<StampMatch> AssociateEvo(const std::vector<double>& first,
                                     const std::vector<double>& second, double max_difference_s,
                                     double offset_s = 0.0);

std::vector<StampMatch> Associate(AssociationKind kind, const std::vector<double>& first,
                                  const std::vector<double>& second, double max_difference_s,
                                  double offset_s = 0.0);

}  // namespace dynref
