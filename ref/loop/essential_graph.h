// ORB-SLAM2 Optimizer::OptimizeEssentialGraph for RGB-D (fixed scale: SE(3) instead of Sim(3);
// Mur-Artal & Tardos, T-RO 2017, Sec. V-D; Strasdat et al., "Scale drift-aware large scale
// monocular SLAM", RSS 2010 for the pose graph) with Ceres (num_threads = 1, residual blocks in
// input order, 20 Levenberg-Marquardt iterations as ORB-SLAM2's optimize(20)).
// Each edge (i, j) measures T_ji = T_jw T_iw^-1 and has the residual
//   E = T_ji_meas * T_iw * T_jw^-1,  r = (angle-axis of R_E, t_E)   (6-vector, identity information,
//   no robust kernel, as ORB-SLAM2's EdgeSim3 with an identity 7x7 information);
// a keyframe in `fixed` is constant (ORB-SLAM2 fixes the loop keyframe).
// Trace (full level): one RESIDUAL per edge, call id `call_id` ("essential#N"), kind "se3edge6",
// observation id "kf<i>-kf<j>", residual at the start and at the end, information 1, weight 1,
// chi2 = robust_loss = |r_end|^2, inlier true (ref/trace/README.md).
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/se3.h"
#include "trace/trace_writer.h"

namespace dynref::loop {

struct PoseGraphEdge {
  int64_t i = 0, j = 0;
  SE3 T_ji = SE3::Identity();  // measurement: T_jw * T_iw^-1
};

struct PoseGraphResult {
  std::map<int64_t, SE3> T_cw;  // every input keyframe
  double chi2_start = 0, chi2_end = 0;  // sums over the edges
  int iterations = 0;
};

// The 6-vector residual of one edge at the given poses.
std::vector<double> PoseGraphResidual(const PoseGraphEdge& e, const SE3& T_iw, const SE3& T_jw);

PoseGraphResult OptimizePoseGraph(const std::map<int64_t, SE3>& T_cw, const std::set<int64_t>& fixed,
                                  const std::vector<PoseGraphEdge>& edges, int iterations, trace::TraceWriter* trace,
                                  const std::string& call_id);

}  // namespace dynref::loop
