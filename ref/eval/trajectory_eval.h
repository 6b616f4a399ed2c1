// ATE and RPE between a ground-truth and an estimated TUM trajectory, reproducing TUM's
// rgbd_benchmark_tools (evaluate_ate.py, evaluate_rpe.py --fixed_delta) and evo (evo_ape -a).
#pragma once
#include <string>
#include <vector>

#include "eval/alignment.h"
#include "eval/statistics.h"
#include "io/association.h"
#include "io/trajectory.h"

namespace dynref {

struct AteOptions {
  AssociationKind association = AssociationKind::kTum;
  double max_difference_s = 0.02;
  AlignMode align = AlignMode::kSE3;
  double offset_s = 0.0;  // added to the estimate's stamps (evaluate_ate.py --offset)
  void Check() const;  // InputError naming the bad field
};

struct AteResult {
  std::vector<StampMatch> matches;  // first = gt index, second = est index
  Similarity3 alignment;            // applied to the estimate
  std::vector<double> errors_m;     // |p_gt - S p_est| per match
  ErrorStats stats;
};

// evaluate_ate.py: associate(gt, est), align est positions onto gt positions, translational
// error per pair. InputError (naming both files) for zero pairs, or < 3 pairs when aligning.
AteResult ComputeAte(const TumTrajectory& gt, const TumTrajectory& est, const AteOptions& options);

enum class DeltaUnit { kSeconds, kFrames };
const char* DeltaUnitName(DeltaUnit unit);  // "s" / "f"

// RPE pair selection and ground-truth lookup.
//   kTum:    evaluate_rpe.py --fixed_delta (closest ground-truth stamp; the pair ending at the last
//            estimate is dropped).
//   kInterp: the same pairs but the one ending at the last estimate is kept, and ground truth is
//            interpolated at the stamp (+ offset): linear position, slerp rotation between the two
//            bracketing ground-truth poses. A pair is dropped when a stamp falls outside the
//            ground truth or between two ground-truth poses more than 2 x the median
//            ground-truth interval apart (a gap).
enum class RpeMode { kTum, kInterp };
const char* RpeModeName(RpeMode mode);  // "tum" / "interp"

struct RpeOptions {
  double delta = 1.0;  // TUM default: 1 s
  DeltaUnit unit = DeltaUnit::kSeconds;
  double offset_s = 0.0;  // added to the estimate's stamps when looking up ground truth
                          // (evaluate_rpe.py --offset); pair selection uses the raw stamps
  RpeMode mode = RpeMode::kTum;
  void Check() const;
};

struct RpePair {
  size_t est_0 = 0, est_1 = 0;            // estimate indices
  size_t gt_0 = 0, gt_1 = 0;              // closest (kTum) / bracketing-later (kInterp) gt index
  double gt_stamp_0 = 0, gt_stamp_1 = 0;  // where ground truth was taken
  double trans_m = 0, rot_rad = 0;
};

struct RpeResult {
  size_t candidate_pairs = 0;       // (i, j) pairs before the ground-truth distance test
  std::vector<RpePair> pairs;       // every used pair (never sub-sampled)
  double gt_median_interval_s = 0;  // median ground-truth stamp interval
  double gt_max_time_difference_s = 0;  // 2 x median interval
  ErrorStats trans_m;
  ErrorStats rot_deg;
};

// evaluate_rpe.py --fixed_delta (`--rpe-mode tum`): for each estimate index i, j = closest index
// (TUM's find_closest_index) to stamp_i + delta (or i + delta frames); dropped when j is the last
// index; both ends matched to the ground-truth stamp closest to stamp + offset, dropped when
// farther than 2 x the median ground-truth interval (kInterp: see RpeMode);
// E = ominus(ominus(est_1, est_0), ominus(gt_1, gt_0)) with
// ominus(a, b) = a^-1 b, i.e. E = dEst * dGt^-1 where d = pose_0^-1 pose_1; trans = |t(E)|,
// rot = acos(clamp((tr R(E) - 1) / 2)). TUM randomly keeps 10,000 pairs when it has more;
// dynref always uses every pair. Duplicate stamps must already be collapsed (kKeepLast).
// InputError for fewer than 2 resulting pairs (as the tool).
RpeResult ComputeRpe(const TumTrajectory& gt, const TumTrajectory& est, const RpeOptions& options);

// TUM's find_closest_index(L, t): binary search that remembers the closest visited element
// (strictly smaller difference wins; an exact hit returns at once). Exposed for tests.
size_t TumFindClosestIndex(const std::vector<double>& sorted, double t);

// evaluate_rpe.py --save: one line per pair "stamp_est0 stamp_est1 stamp_gt0 stamp_gt1
// trans_error rot_error" (m, rad; 17 significant digits), written atomically.
void WriteRpePairs(const std::string& path, const TumTrajectory& est, const RpeResult& rpe);

}  // namespace dynref
