#include "io/trajectory.h"

#include <cmath>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "io/stamped_list.h"

namespace dynref {

std::vector<double> TumTrajectory::Stamps() const {
  std::vector<double> s;
  s.reserve(poses.size());
  for (const auto& p : poses) s.push_back(p.stamp);
  return s;
}

TumTrajectory ReadTumTrajectory(const std::string& path, const TumReadOptions& options) {
  const bool allow_equal = options.duplicates != DuplicateStamps::kError;
  const std::vector<StampedLine> rows = ReadStampedList(path, 7, 7, allow_equal);
  static const char* kNames[7] = {"tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  TumTrajectory traj;
  traj.path = path;
  for (const StampedLine& row : rows) {
    double v[7];
    for (int k = 0; k < 7; ++k) {
      v[k] = ParseNumberField(row.fields[k], path, row.line, std::string("field ") + kNames[k]);
      if (!std::isfinite(v[k]))
        throw InputError(path, row.line,
                         std::string("pose field ") + kNames[k] + " is " + row.fields[k] +
                             " (NaN/inf pose)");
      // Squares of positions enter sums of squares (ATE, alignment): beyond 1e9 m they overflow or
      // lose every digit (1e300 gave "rmse inf" with exit 0; issue 20 item 9). 1e9 m = 7 AU.
      if (k < 3 && std::abs(v[k]) > 1e9)
        throw InputError(path, row.line,
                         std::string("pose field ") + kNames[k] + " = " + row.fields[k] +
                             " m is beyond 1e9 m (not a camera trajectory)");
    }
    const double qnorm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
    if (!(std::abs(qnorm - 1.0) <= options.quaternion_norm_tolerance))
      throw InputError(path, row.line,
                       "quaternion not normalised: |q| = " + FormatFixed(qnorm, 6) +
                           " (accepted within " + FormatDouble17(options.quaternion_norm_tolerance) +
                           " of 1)");
    if (qnorm != 1.0) ++traj.quaternions_normalised;
    StampedPose pose;
    pose.stamp = row.stamp;
    pose.T_wc = MakeSE3(Eigen::Vector3d(v[0], v[1], v[2]),
                        Eigen::Quaterniond(v[6], v[3], v[4], v[5]));  // normalises
    if (!traj.poses.empty() && traj.poses.back().stamp == row.stamp) {
      ++traj.duplicate_stamps;
      if (options.duplicates == DuplicateStamps::kKeepLast) {
        ++traj.duplicates_dropped;
        traj.poses.back() = pose;
        traj.lines.back() = row.line;
        continue;
      }
    }
    traj.poses.push_back(pose);
    traj.lines.push_back(row.line);
  }
  if (traj.poses.empty() && !options.allow_empty)
    throw InputError(path, "no poses (empty trajectory)");
  return traj;
}

std::string FormatTumPoseLine(const StampedPose& pose, const TumWriteOptions& options) {
  Eigen::Quaterniond q(pose.T_wc.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d t = pose.T_wc.translation();
  const double values[7] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
  const bool fixed = options.format == TumWriteOptions::Format::kFixed;
  std::string line = fixed ? FormatFixed(pose.stamp, options.stamp_decimals)
                           : FormatDouble17(pose.stamp);
  for (double v : values) {
    line += ' ';
    line += fixed ? FormatFixed(v, options.value_decimals) : FormatDouble17(v);
  }
  return line;
}

void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses,
                        const TumWriteOptions& options) {
  std::string out;
  if (!options.header.empty()) {
    std::istringstream h(options.header);
    std::string l;
    while (std::getline(h, l)) out += "# " + l + "\n";
  }
  for (const StampedPose& p : poses) out += FormatTumPoseLine(p, options) + "\n";
  AtomicWriteFile(path, out);
}

}  // namespace dynref
