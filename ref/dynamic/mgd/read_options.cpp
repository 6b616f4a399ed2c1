// MgdOptions from mgd.probability's params; every key is required (configs/mgd*.yaml give each
// with its source).
#include <stdexcept>

#include "core/error.h"
#include "dynamic/mgd/read_options.h"
#include "dynamic/mgd/stages.h"
#include "io/coco_classes.h"

namespace dynref::mgd {

MgdOptions ReadOptions(const ParamMap& p) {
  p.RequireKnownKeys({"min_confidence", "threshold_scale", "dynamic_classes", "initial_pose_out_of_box", "after_local_map_search", "p_init_box", "p_init_free",
                      "delta", "match_radius_px", "use_ls", "use_pro", "use_mf", "d_th_ls_px", "theta_th_ls_rad",
                      "a_ls", "angle_form", "min_velocity_px", "d_th_pro_px", "a_pro", "d_th_mf_px", "a_mf", "w_ls",
                      "w_pro", "w_mf", "a", "smoothing", "diffusion", "radius_m", "tau_dyn", "weight", "line_cue_form",
                      "line_match_angle_deg", "line_match_radius_px", "line_match_bits"});
  MgdOptions o;
  o.min_confidence = p.GetDouble("min_confidence");
  o.threshold_scale = p.GetString("threshold_scale");
  o.dynamic_class_ids = p.GetCocoClassIds("dynamic_classes");
  o.initial_pose_out_of_box = p.GetBool("initial_pose_out_of_box");
  o.after_local_map_search = p.GetBool("after_local_map_search");
  o.p_init_box = p.GetDouble("p_init_box");
  o.p_init_free = p.GetDouble("p_init_free");
  o.delta = p.GetDouble("delta");
  o.match_radius_px = p.GetDouble("match_radius_px");
  o.use_ls = p.GetBool("use_ls");
  o.use_pro = p.GetBool("use_pro");
  o.use_mf = p.GetBool("use_mf");
  o.d_th_ls_px = p.GetDouble("d_th_ls_px");
  o.theta_th_ls_rad = p.GetDouble("theta_th_ls_rad");
  o.a_ls = p.GetDouble("a_ls");
  auto choice = [&](const std::string& key, const std::vector<std::string>& names) {
    const std::string v = p.GetString(key);
    for (size_t i = 0; i < names.size(); ++i)
      if (v == names[i]) return static_cast<int>(i);
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : " | ") + n;
    throw InputError(p.Get(key).file, p.Get(key).line, "mgd.probability: " + key + " must be " + list + ", got " + v);
  };
  o.angle_form = choice("angle_form", {"angle_to_mean", "literal_arctan"}) == 0 ? AngleForm::kAngleToMean
                                                                               : AngleForm::kLiteralArctan;
  o.min_velocity_px = p.GetDouble("min_velocity_px");
  o.d_th_pro_px = p.GetDouble("d_th_pro_px");
  o.a_pro = p.GetDouble("a_pro");
  o.d_th_mf_px = p.GetDouble("d_th_mf_px");
  o.a_mf = p.GetDouble("a_mf");
  o.w_ls = p.GetDouble("w_ls");
  o.w_pro = p.GetDouble("w_pro");
  o.w_mf = p.GetDouble("w_mf");
  o.a = p.GetDouble("a");
  o.smoothing = choice("smoothing", {"new_evidence", "old_evidence"}) == 0 ? SmoothingForm::kNewEvidence
                                                                          : SmoothingForm::kOldEvidence;
  o.diffusion = p.GetBool("diffusion");
  o.radius_m = p.GetDouble("radius_m");
  o.tau_dyn = p.GetDouble("tau_dyn");
  o.line_cue_form = choice("line_cue_form", {"pseudo_point", "normal"}) == 0 ? LineCueForm::kPseudoPoint
                                                                           : LineCueForm::kNormal;
  o.line_match_angle_deg = p.GetDouble("line_match_angle_deg");
  o.line_match_radius_px = p.GetDouble("line_match_radius_px");
  o.line_match_bits = static_cast<int>(p.GetInt("line_match_bits"));
  o.weight = choice("weight", {"one_minus_p", "none"}) == 0 ? WeightForm::kOneMinusP : WeightForm::kNone;
  try {
    o.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage mgd.probability: " + std::string(e.what()));
  }
  return o;
}

const MgdOptions& RequireOptions(const MgdState& state, const std::string& stage) {
  if (!state.configured) throw std::logic_error(stage + " needs mgd.probability in the stage list");
  return state.options;
}

}  // namespace dynref::mgd

namespace dynref {

// Ranges (issue 37): thresholds and radii > 0 (a negative one silently disabled its cue),
// probabilities, weights and smoothing factors in [0, 1], every value finite.
void RegisterMgdParams(MethodRegistry& registry) {
  registry.AddParams(
      "mgd.probability",
      {{Real("min_confidence", 0, 1), Choice("threshold_scale", {"detector", "raw"}), Names("dynamic_classes"), Flag("initial_pose_out_of_box"), Flag("after_local_map_search"),
        Real("p_init_box", 0, 1),
        Real("p_init_free", 0, 1), Real("delta", 0, 1), RealAbove("match_radius_px", 0, 1000), Flag("use_ls"),
        Flag("use_pro"), Flag("use_mf"), RealAbove("d_th_ls_px", 0, 1000), RealAbove("theta_th_ls_rad", 0, 3.2),
        Real("a_ls", 0, 1), Choice("angle_form", {"angle_to_mean", "literal_arctan"}), Real("min_velocity_px", 0, 1000),
        RealAbove("d_th_pro_px", 0, 1000), RealAbove("a_pro", 0, 1000), RealAbove("d_th_mf_px", 0, 1000),
        RealAbove("a_mf", 0, 1000), Real("w_ls", 0, 10), Real("w_pro", 0, 10), Real("w_mf", 0, 10), Real("a", 0, 1),
        Choice("smoothing", {"new_evidence", "old_evidence"}), Flag("diffusion"), RealAbove("radius_m", 0, 10),
        Real("tau_dyn", 0, 1), Choice("weight", {"one_minus_p", "none"}),
        Choice("line_cue_form", {"pseudo_point", "normal"}), BelowHi(RealAbove("line_match_angle_deg", 0, 90)),
        RealAbove("line_match_radius_px", 0, 1000), Integer("line_match_bits", 0, 256)}});
  registry.AddParams("mgd.boxes", {});       // its options live in mgd.probability
  registry.AddParams("mgd.reprojection", {});
  registry.AddRequirement("mgd.boxes", "mgd.probability");
  registry.AddRequirement("mgd.reprojection", "mgd.probability");
  registry.AddRequirement("mgd.probability", "mgd.boxes");
}

}  // namespace dynref
