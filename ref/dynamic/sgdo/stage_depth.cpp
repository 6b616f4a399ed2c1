// sgdo.depth (kAfterInitialPose). seed 001, Sec. 3.4 Eq. (8)-(9) and Sec. 3.5:
// every surviving keypoint with depth is moved into the tracking reference keyframe with the
// INITIAL pose T_cw^(0) (spec 001 E4: two-pass tracking, this hook sits between the passes),
// eps = (z_k - d_k) / d_k against the keyframe depth map (nearest pixel, E5), rejected iff
// reject && |eps| > eta, and weighted omega = exp(-lambda eps^2) iff weight (skipped tests keep
// omega = 1). The weight multiplies the residual information in pose optimisation and is stored
// on the keyframe observation for local BA (backbone contract, spec 001 E6/E7).
#include "dynamic/sgdo/stages.h"

namespace dynref::sgdo {

DepthStage::DepthStage(const ParamMap& p) {
  p.RequireKnownKeys({"eta", "lambda", "reject", "weight"});
  options_.eta = p.GetDouble("eta");
  options_.lambda = p.GetDouble("lambda");
  reject_ = p.GetBool("reject");
  weight_ = p.GetBool("weight");
  if (!reject_ && !weight_) throw InputError(p.file, p.line, "sgdo.depth: reject and weight both false (stage does nothing)");
  try {
    options_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage sgdo.depth: " + std::string(e.what()));
  }
}

void DepthStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  trace::TraceWriter& tr = ctx.trace;
  const KeyFrame* kf = ctx.reference_kf;
  // A reference keyframe that local mapping culled has released its images and keeps only a
  // pose relative to its parent (issue 21 defect 5): test against the nearest live ancestor.
  int culled_hops = 0;
  while (kf != nullptr && kf->bad && culled_hops < 1000) kf = ctx.map.kf(kf->parent), ++culled_hops;
  if (culled_hops > 0) tr.FrameCount(name(), "reference_kf_culled_hops", culled_hops);
  if (!f.has_pose || kf == nullptr || kf->bad || kf->frame.depth_m.empty()) {
    tr.FrameCount(name(), "skipped_no_pose_or_kf", 1);
    return;
  }
  const Intrinsics K = ctx.camera.Pinhole();
  const Eigen::Isometry3d T_kc = kf->T_cw * f.T_cw.inverse();
  const double kf_id = static_cast<double>(kf->id);
  const bool full = tr.full_enabled();
  if (full) {
    // The keyframe's pose at the test (issue 32): with the frame's POSE "initial" it gives T_kc,
    // which `trace verify` needs to recompute Eq. (8)-(9); keyframe poses are in no other record.
    // Rows 0..2 of T_kw (keyframe_from_world) row-major; p = 0: a geometry carrier.
    static const char* const kNames[12] = {"T_kw[0]", "T_kw[1]", "T_kw[2]", "T_kw[3]", "T_kw[4]", "T_kw[5]",
                                           "T_kw[6]", "T_kw[7]", "T_kw[8]", "T_kw[9]", "T_kw[10]", "T_kw[11]"};
    std::vector<trace::NamedValue> pose;
    const Eigen::Matrix4d T_kw = kf->T_cw.matrix();
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 4; ++col) pose.push_back({kNames[4 * r + col], T_kw(r, col)});
    tr.ProbabilityUpdate("sgdo.depth.kf", trace::EntityKind::kKeyFrame, "kf" + std::to_string(kf->id), pose, 0.0, 0.0);
  }
  int64_t tested = 0, rejected = 0, skipped = 0;
  double weight_sum = 0;
  for (int i = 0; i < static_cast<int>(f.N()); ++i) {
    if (f.IsExcluded(i)) continue;
    const cv::Point2f& p = f.keys_un[i].pt;
    const DepthCheck c = CheckDepthConsistency(p.x, p.y, f.depth[i], K, T_kc, kf->frame.depth_m, &ctx.camera);
    const double omega = c.tested ? StaticWeight(c.eps, options_.lambda) : 1.0;
    const bool reject = reject_ && c.tested && std::abs(c.eps) > options_.eta;
    // `weight`: the static weight the feature carries into pose optimisation after this stage
    // (omega when weights are on and the point is kept, else its previous weight).
    if (full)
      tr.ProbabilityUpdate(name(), trace::EntityKind::kFeature, f.FeatureId(i),
                           {{"kf", kf_id}, {"depth_i_m", f.depth[i]}, {"u_k", c.u_k}, {"v_k", c.v_k},
                            {"z_k", c.z_k}, {"d_k", c.d_k}, {"eps", c.eps}, {"eta", options_.eta},
                            {"lambda", options_.lambda}, {"tested", c.tested ? 1.0 : 0.0},
                            {"omega", omega}, {"weight", weight_ && !reject ? omega : f.Weight(i)}},
                           // Trace convention p(dynamic) (overlay colour): 1 - static weight, and 1
                           // for a rejected point whatever the weight switch (issue 21).
                           1.0 - f.Weight(i), reject ? 1.0 : 1.0 - (weight_ ? omega : f.Weight(i)));
    if (c.tested) ++tested; else ++skipped;
    if (reject) {
      ctx.frame.Exclude(i, name(), "depth-eps");
      ++rejected;
      continue;
    }
    tr.Decision(name(), trace::EntityKind::kFeature, f.FeatureId(i), true,
                c.tested ? "consistent" : "untested:" + c.skip_reason);
    if (weight_) {
      ctx.frame.SetWeight(i, omega);
      weight_sum += omega;
    }
  }
  tr.FrameCount(name(), "reference_kf", kf->id);
  tr.FrameCount(name(), "tested", tested);
  tr.FrameCount(name(), "skipped", skipped);
  tr.FrameCount(name(), "rejected", rejected);
  // Sum of weights in 1/1000 (integer counter): a compact per-frame summary of omega.
  if (weight_) tr.FrameCount(name(), "weight_sum_milli", static_cast<int64_t>(std::llround(weight_sum * 1000)));
}

}  // namespace dynref::sgdo
