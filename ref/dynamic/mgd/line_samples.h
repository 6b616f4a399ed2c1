// MGD-SLAM line samples (seed 000 Sec. 3.4, spec step 11 and E12): the start, midpoint and end of
// every frame line go through steps 7-10 as pseudo-points; a line is unreliable when
// max(P_s, P_m, P_e) > tau_dyn (weight 0: out of pose optimisation, local BA and the map), else
// its weight is 1 - max P (spec E13 as for points). Planes are always static (spec step 12).
//
// Correspondence: the previous frame's line of the same map line, else an LBD match
// (structure::MatchLinesToPrevious); sample k pairs with sample k of the previous line, or 2 - k
// when that segment runs the other way. Cue forms (options.line_cue_form):
//  - pseudo_point (spec E12, proposed): P_LS and P_mf of the sample pair exactly as for points.
//    Endpoints slide along a line between detections (aperture), so both cues also see that slide;
//  - normal: only what a line can show. P_LS from the normal flow d = |l_k . x^{k-1} + n . vbar|
//    (l_k the current line, n its unit normal; dtheta not observable, set to theta_th so the angle
//    term is neutral). P_mf from the sample moved with its depth: d = |l_k . pi(K, T_{k,k-1}
//    X^{k-1})| (two views of a line satisfy any epipolar geometry, so the pseudo-point epipolar
//    distance only measures the slide).
// P_pro is not computed for lines (its backward term needs a point correspondence): logit 0.
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include "dynamic/mgd/state.h"
#include "method/stage.h"
#include "structure/line_frame_matching.h"

namespace dynref::mgd {

struct LineSampleNodes {
  std::vector<structure::LineCorrespondence> corr;
  std::vector<std::array<double, 3>> p_prev, p_smooth;  // per line and sample
  std::vector<std::array<Eigen::Vector3d, 3>> X;        // camera frame, for diffusion
  std::vector<std::array<bool, 3>> has_X;
  size_t size() const { return p_smooth.size(); }
};

// Box flags of the samples s, m, e of every frame line (Flag_d per sample, spec step 6).
std::vector<std::array<uint8_t, 3>> LineSampleBoxFlags(const Frame& f, const MgdOptions& o);

// Initialisation frame: P = P_init(Flag_d) per sample; a line above tau_dyn gets weight 0, else
// 1 - max P (as mgd.boxes does for points). Sets state.prev_line_p.
void InitialiseLinePriors(StageContext& ctx, const MgdOptions& o, MgdState& s);

// Steps 7-9 for every line sample of the current frame (traced at --trace full).
// vbar / F / T_cur_prev may be nullptr (not available: the cue is not computable).
LineSampleNodes EvaluateLineSamples(StageContext& ctx, const MgdOptions& o, const MgdState& s,
                                    const Eigen::Vector2d* vbar, const Eigen::Matrix3d* F, const SE3* T_cur_prev,
                                    const std::string& stage);

// Steps 13 and 15 for lines: p_diffused holds 3 values per line (s, m, e). Writes weights, the
// map line probabilities and state.prev_line_p; returns the number of lines taken out.
int64_t DecideLines(StageContext& ctx, const MgdOptions& o, MgdState& s, const LineSampleNodes& nodes,
                    const std::vector<double>& p_diffused, const std::vector<int>& neighbours,
                    const std::string& stage);

}  // namespace dynref::mgd
