#include "eval/trajectory_eval.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"

namespace dynref {

void AteOptions::Check() const {
  if (!(max_difference_s > 0) || !std::isfinite(max_difference_s))
    throw InputError("--max-diff", "must be a finite number > 0, got " +
                                       FormatDouble17(max_difference_s));
  if (!std::isfinite(offset_s))
    throw InputError("--offset", "must be a finite number, got " + FormatDouble17(offset_s));
}

const char* DeltaUnitName(DeltaUnit unit) { return unit == DeltaUnit::kSeconds ? "s" : "f"; }

const char* RpeModeName(RpeMode mode) { return mode == RpeMode::kTum ? "tum" : "interp"; }

void RpeOptions::Check() const {
  if (!(delta > 0) || !std::isfinite(delta))
    throw InputError("--delta", "must be a finite number > 0, got " + FormatDouble17(delta));
  // TUM's closest-index search compares stamp + delta in double: beyond ~1e9 the stamps'
  // differences vanish and it returns meaningless (even backward) pairs.
  if (delta > 1e9) throw InputError("--delta", "must be <= 1e9, got " + FormatDouble17(delta));
  // A frame delta counts poses: 0.5 frames would pair every pose with itself (issue 37).
  if (unit == DeltaUnit::kFrames && delta != std::floor(delta))
    throw InputError("--delta", "with --delta-unit f must be a whole number of frames >= 1, got " + FormatDouble17(delta));
  if (!std::isfinite(offset_s))
    throw InputError("--offset", "must be a finite number, got " + FormatDouble17(offset_s));
}

AteResult ComputeAte(const TumTrajectory& gt, const TumTrajectory& est,
                     const AteOptions& options) {
  options.Check();
  AteResult r;
  r.matches = Associate(options.association, gt.Stamps(), est.Stamps(), options.max_difference_s,
                        options.offset_s);
  if (r.matches.empty())
    throw InputError(est.path, "zero associated pairs with ground truth " + gt.path + " within " +
                                   FormatDouble17(options.max_difference_s) +
                                   " s (association " +
                                   AssociationKindName(options.association) + ")");
  std::vector<Eigen::Vector3d> p_est, p_gt;
  for (const StampMatch& m : r.matches) {
    p_gt.push_back(gt.poses[m.first].T_wc.translation());
    p_est.push_back(est.poses[m.second].T_wc.translation());
  }
  if (options.align != AlignMode::kNone && r.matches.size() < 3)
    throw InputError(est.path, "only " + std::to_string(r.matches.size()) +
                                   " associated pair(s) with " + gt.path + "; alignment " +
                                   AlignModeName(options.align) + " needs at least 3");
  try {
    r.alignment = AlignPoints(p_est, p_gt, options.align);
  } catch (const std::invalid_argument& e) {  // e.g. sim3 on a constant estimate: name the file
    throw InputError(est.path, e.what());
  }
  for (size_t k = 0; k < p_est.size(); ++k)
    r.errors_m.push_back((r.alignment.Apply(p_est[k]) - p_gt[k]).norm());
  r.stats = ComputeErrorStats(r.errors_m);
  return r;
}

size_t TumFindClosestIndex(const std::vector<double>& L, double t) {
  size_t beginning = 0, end = L.size(), best = 0;
  double difference = std::abs(L[0] - t);
  while (beginning < end) {
    const size_t middle = (end + beginning) / 2;
    if (std::abs(L[middle] - t) < difference) {
      difference = std::abs(L[middle] - t);
      best = middle;
    }
    if (t == L[middle]) return middle;
    if (L[middle] > t)
      end = middle;
    else
      beginning = middle + 1;
  }
  return best;
}

namespace {

// Ground truth at stamp t: linear position and slerp rotation between the bracketing poses
// gt[k-1], gt[k] (k returned). False outside the ground truth or inside a gap (bracket wider
// than max_gap_s).
bool InterpolateGroundTruth(const TumTrajectory& gt, const std::vector<double>& stamps, double t,
                            double max_gap_s, size_t* k_out, SE3* pose) {
  const size_t k = std::lower_bound(stamps.begin(), stamps.end(), t) - stamps.begin();
  if (k == stamps.size()) return false;
  if (stamps[k] == t) {
    *k_out = k;
    *pose = gt.poses[k].T_wc;
    return true;
  }
  if (k == 0 || stamps[k] - stamps[k - 1] > max_gap_s) return false;
  const double s = (t - stamps[k - 1]) / (stamps[k] - stamps[k - 1]);
  const SE3& a = gt.poses[k - 1].T_wc;
  const SE3& b = gt.poses[k].T_wc;
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(a.linear()).slerp(s, Eigen::Quaterniond(b.linear())).normalized();
  *k_out = k;
  *pose = MakeSE3(a.translation() + s * (b.translation() - a.translation()), q);
  return true;
}

}  // namespace

RpeResult ComputeRpe(const TumTrajectory& gt, const TumTrajectory& est,
                        const RpeOptions& options) {
  options.Check();
  const std::vector<double> stamps_gt = gt.Stamps(), stamps_est = est.Stamps();
  if (stamps_gt.size() < 2 || stamps_est.size() < 2)
    throw InputError(stamps_gt.size() < 2 ? gt.path : est.path,
                     "RPE needs at least 2 poses in each trajectory");
  for (size_t k = 1; k < stamps_gt.size(); ++k)
    if (!(stamps_gt[k] > stamps_gt[k - 1]))
      throw InputError(gt.path, "RPE needs strictly increasing stamps (duplicates collapsed)");
  RpeResult r;
  // gt_interval = numpy.median of consecutive differences.
  std::vector<double> intervals;
  for (size_t k = 1; k < stamps_gt.size(); ++k) intervals.push_back(stamps_gt[k] - stamps_gt[k - 1]);
  std::sort(intervals.begin(), intervals.end());
  const size_t m = intervals.size() / 2;
  r.gt_median_interval_s =
      intervals.size() % 2 ? intervals[m] : 0.5 * (intervals[m - 1] + intervals[m]);
  r.gt_max_time_difference_s = 2 * r.gt_median_interval_s;

  std::vector<double> index_est;  // TUM: stamps for unit s, range(len) for unit f
  for (size_t i = 0; i < stamps_est.size(); ++i)
    index_est.push_back(options.unit == DeltaUnit::kSeconds ? stamps_est[i]
                                                            : static_cast<double>(i));
  const size_t last = stamps_est.size() - 1;
  const bool interp = options.mode == RpeMode::kInterp;
  std::vector<double> trans, rot_deg;
  for (size_t i = 0; i < stamps_est.size(); ++i) {
    const size_t j = TumFindClosestIndex(index_est, index_est[i] + options.delta);
    if (j == last && !interp) continue;
    if (interp && j == i && i == last) continue;  // the last pose paired with itself
    // A pose paired with itself (a delta in seconds shorter than half the estimate's frame
    // interval) has zero error by construction: refuse instead of diluting the statistics.
    if (j == i)
      throw InputError("--delta", "delta = " + FormatDouble17(options.delta) +
                                      " s pairs estimate pose " + std::to_string(i) + " (stamp " +
                                      FormatDouble17(stamps_est[i]) +
                                      ") with itself: it is shorter than half the estimate's frame interval; give a "
                                      "larger --delta or --delta-unit f");
    ++r.candidate_pairs;
    RpePair p;
    p.est_0 = i;
    p.est_1 = j;
    p.gt_stamp_0 = stamps_est[i] + options.offset_s;
    p.gt_stamp_1 = stamps_est[j] + options.offset_s;
    SE3 gt_0, gt_1;
    if (interp) {
      if (!InterpolateGroundTruth(gt, stamps_gt, p.gt_stamp_0, r.gt_max_time_difference_s, &p.gt_0,
                                  &gt_0) ||
          !InterpolateGroundTruth(gt, stamps_gt, p.gt_stamp_1, r.gt_max_time_difference_s, &p.gt_1,
                                  &gt_1))
        continue;
    } else {
      p.gt_0 = TumFindClosestIndex(stamps_gt, p.gt_stamp_0);
      p.gt_1 = TumFindClosestIndex(stamps_gt, p.gt_stamp_1);
      if (std::abs(stamps_gt[p.gt_0] - p.gt_stamp_0) > r.gt_max_time_difference_s ||
          std::abs(stamps_gt[p.gt_1] - p.gt_stamp_1) > r.gt_max_time_difference_s)
        continue;
      p.gt_stamp_0 = stamps_gt[p.gt_0];
      p.gt_stamp_1 = stamps_gt[p.gt_1];
      gt_0 = gt.poses[p.gt_0].T_wc;
      gt_1 = gt.poses[p.gt_1].T_wc;
    }
    const SE3 d_est = est.poses[i].T_wc.inverse() * est.poses[j].T_wc;
    const SE3 d_gt = gt_0.inverse() * gt_1;
    const SE3 error = d_est * d_gt.inverse();
    p.trans_m = error.translation().norm();
    p.rot_rad = RotationAngleRad(error.linear());
    r.pairs.push_back(p);
    trans.push_back(p.trans_m);
    rot_deg.push_back(p.rot_rad * 180.0 / M_PI);
  }
  // Say what is missing (issue 20 item 10: "do the stamps overlap?" was printed for a 9-frame
  // clip whose stamps do overlap but whose span is shorter than delta).
  const char* unit = options.unit == DeltaUnit::kSeconds ? " s" : " frames";
  if (r.candidate_pairs < 2)
    throw InputError(est.path, "RPE: only " + std::to_string(r.candidate_pairs) + " pair(s) of estimate poses are delta = " +
                                   FormatDouble17(options.delta) + unit + " apart (the estimate has " +
                                   std::to_string(stamps_est.size()) + " poses over " +
                                   FormatFixed(stamps_est.back() - stamps_est.front(), 3) +
                                   " s); need 2: give a smaller --delta or --delta-unit f");
  if (r.pairs.size() < 2)
    throw InputError(est.path, "RPE: " + std::to_string(r.pairs.size()) + " of " + std::to_string(r.candidate_pairs) +
                                   " pose pairs have ground truth " + gt.path + " within 2 x its median interval (" +
                                   FormatFixed(r.gt_max_time_difference_s, 6) +
                                   " s) of both stamps; need 2: do the stamps overlap (see --offset)?");
  r.trans_m = ComputeErrorStats(trans);
  r.rot_deg = ComputeErrorStats(rot_deg);
  return r;
}

void WriteRpePairs(const std::string& path, const TumTrajectory& est, const RpeResult& rpe) {
  std::string text;
  for (const RpePair& p : rpe.pairs) {
    text += FormatDouble17(est.poses[p.est_0].stamp) + " " + FormatDouble17(est.poses[p.est_1].stamp) +
            " " + FormatDouble17(p.gt_stamp_0) + " " + FormatDouble17(p.gt_stamp_1) + " " +
            FormatDouble17(p.trans_m) + " " + FormatDouble17(p.rot_rad) + "\n";
  }
  AtomicWriteFile(path, text);
}

}  // namespace dynref
