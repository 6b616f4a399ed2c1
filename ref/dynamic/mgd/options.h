// MGD-SLAM (seed 000) options: every value of spec 000 (c) with its source; each reading the
// spec marks ambiguous is a switch with the proposed reading as default. Read from
// configs/mgd*.yaml (every key required there, with its source).
#pragma once
#include <set>
#include <string>
#include <vector>

namespace dynref::mgd {

// spec 000 E1: which term of the smoothing gets the factor a.
enum class SmoothingForm { kNewEvidence /* (1-a) P_prev + a S (proposed) */, kOldEvidence /* a P_prev + (1-a) S */ };
// spec 000 E5: dtheta of P_LS.
enum class AngleForm { kAngleToMean /* unsigned angle between v_i and vbar (proposed) */, kLiteralArctan /* arctan(dv/du) */ };
// spec 000 E13: observation weight of a kept feature.
// spec 000 E12: cues of a line sample (line_samples.h).
enum class LineCueForm { kPseudoPoint /* samples as points (proposed) */, kNormal /* normal flow, depth transfer */ };
enum class WeightForm { kOneMinusP /* w = 1 - P (proposed) */, kNone /* w = 1 */ };

struct MgdOptions {
  // Box flags (Sec. 3.3).
  double min_confidence = 0.5;                 // paper 0.5 (for its YOLO; issue 39: mapped to the source)
  std::string threshold_scale = "detector";    // "detector": calibrated to the source; "raw": 0.5 as is
  std::vector<int> dynamic_class_ids = {0, 24, 56, 26, 28};  // person, backpack, chair, handbag, suitcase (spec (c))
  bool initial_pose_out_of_box = true;         // spec E10: initial pose from out-of-box matches only (weight 0 in boxes)
  // Temporal inheritance (Sec. 3.4): "a 3D map point observed in F_k" inherits from "the
  // corresponding map representation", so the update runs after the local-map search has
  // associated the frame's features (issue 38); false = right after the initial pose, before it
  // (dynref before issue 38: half the final associations missed their map point's P).
  bool after_local_map_search = true;
  double p_init_box = 0.5;                     // P_init of a new feature in a box (paper)
  double p_init_free = 0.0;                    // ... outside boxes (paper)
  double delta = 0.6;                          // descriptor similarity (Table 1): match iff Hamming <= (1 - delta) 256
  double match_radius_px = 15;                 // not stated: window of the previous-frame descriptor search
  // Cues (Sec. 3.5).
  bool use_ls = true, use_pro = true, use_mf = true;  // ablations: one cue only
  double d_th_ls_px = 3, theta_th_ls_rad = 2, a_ls = 0.5;
  AngleForm angle_form = AngleForm::kAngleToMean;
  double min_velocity_px = 0.5;                // spec E5: dtheta = 0 below this speed
  double d_th_pro_px = 2, a_pro = 1.0;
  double d_th_mf_px = 2, a_mf = 1.0;
  double w_ls = 0.4, w_pro = 0.4, w_mf = 0.2;  // Table 1
  // Smoothing and diffusion (Sec. 3.4).
  double a = 0.7;                              // Table 1
  SmoothingForm smoothing = SmoothingForm::kNewEvidence;
  bool diffusion = true;
  double radius_m = 0.15;                      // Table 1
  // Line samples (Sec. 3.4, spec step 11): frame-to-frame line correspondence and cue form.
  LineCueForm line_cue_form = LineCueForm::kPseudoPoint;
  double line_match_angle_deg = 3;             // paper Sec. 3.2 tau_theta (spec E14 gate)
  double line_match_radius_px = 15;            // as match_radius_px
  int line_match_bits = 90;                    // as the backbone's line_match_bits
  // Suppression and weighting (Sec. 3.6).
  double tau_dyn = 0.5;                        // not stated (spec (c))
  WeightForm weight = WeightForm::kOneMinusP;
  void Check() const;                          // std::invalid_argument naming the field
};

}  // namespace dynref::mgd
