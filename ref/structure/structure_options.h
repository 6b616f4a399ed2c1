// Options of the structure landmarks (lines and planes, seed 000; issue 13). They are backbone
// keys (ref/pipeline/backbone_keys.cpp: `lines`, `planes`, `line_*`, `plane_*`), off by
// default: with both off the backbone is the point-only ORB-SLAM2 one, bit for bit.
#pragma once
#include "features/lines.h"
#include "features/planes.h"
#include "optim/optim.h"

namespace dynref::structure {

struct StructureOptions {
  bool lines = false;
  bool planes = false;
  features::LineOptions line;
  features::PlaneOptions plane;
  // Association of frame lines to map lines at the current pose estimate.
  int line_match_bits = 90;          // LBD Hamming distance gate (256 bits)
  double line_match_angle_deg = 3;   // |theta_projected - theta_observed| (spec E14: tau_theta)
  double line_match_px = 15;         // midpoint distances between projected and observed lines
  double line_collinear_m = 0.02;    // 3-D samples collinear within this (+1 % of depth)
  double line_min_3d_length_m = 0.05;
  // e_par (the companion line's collinearity term) in the line residual (spec 000 step 14).
  bool line_parallel_term = true;
  // Association of frame planes to map planes, and merging of map planes.
  double plane_match_angle_deg = 10;
  double plane_match_dist_m = 0.1;
  double plane_merge_angle_deg = 5;
  double plane_merge_dist_m = 0.05;
  optim::StructureResidualOptions residual;
  // How much an inlier line / plane counts beside an inlier point in ORB-SLAM2's tracking
  // thresholds (motion model >= 20 matches, >= 10 / 30 / 50 inliers, keyframe c2 > 15).
  double line_count_weight = 1;
  double plane_count_weight = 3;
  bool enabled() const { return lines || planes; }
  void Check() const;  // InputError naming the field
};

}  // namespace dynref::structure
