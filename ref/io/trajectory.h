// TUM trajectory files ("stamp tx ty tz qx qy qz qw", T_wc = world_from_camera): a validating
// reader and an atomic writer.
#pragma once
#include <string>
#include <vector>

#include "core/se3.h"

namespace dynref {

// What to do with two consecutive lines carrying the same timestamp (the official TUM fr2_desk
// ground truth has one such pair).
enum class DuplicateStamps {
  kKeepLast,  // TUM rgbd_benchmark_tools: the file is read into a dict, the later line wins
  kKeepAll,   // evo: every line is a pose (its nearest-neighbour search finds the first one)
  kError,
};

struct TumTrajectory {
  std::string path;
  std::vector<StampedPose> poses;   // T_wc, non-decreasing stamps
  std::vector<int> lines;           // 1-based source line of each pose
  int duplicate_stamps = 0;         // lines whose stamp equalled the previous line's
  int duplicates_dropped = 0;       // of those, dropped by kKeepLast
  int quaternions_normalised = 0;   // |q| != 1 within tolerance, normalised

  std::vector<double> Stamps() const;
};

struct TumReadOptions {
  DuplicateStamps duplicates = DuplicateStamps::kKeepLast;
  bool allow_empty = false;
  // A quaternion whose norm is within this of 1 is normalised; farther is an error.
  double quaternion_norm_tolerance = 1e-3;
};

// InputError naming file and line for: missing file, a line without exactly 8 fields,
// non-numeric or non-finite (NaN/inf) field, |q| not within tolerance of 1, decreasing stamps,
// (duplicates per options), no pose at all (unless allow_empty).
TumTrajectory ReadTumTrajectory(const std::string& path, const TumReadOptions& options = {});

struct TumWriteOptions {
  enum class Format {
    kPrecise17,  // every number "%.17g": reading the file back gives the same doubles
    kFixed,      // ORB-SLAM2 SaveTrajectoryTUM style: stamp %.6f, pose values %.9f
  };
  Format format = Format::kPrecise17;
  int stamp_decimals = 6;   // kFixed only
  int value_decimals = 9;   // kFixed only
  std::string header;       // optional comment lines (each written with a leading "# ")
};

// Writes atomically (temp file + rename). Quaternions are unit, with qw >= 0.
void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses,
                        const TumWriteOptions& options = {});
// One line (no newline) in the given format; exposed for tests and other writers.
std::string FormatTumPoseLine(const StampedPose& pose, const TumWriteOptions& options = {});

}  // namespace dynref
