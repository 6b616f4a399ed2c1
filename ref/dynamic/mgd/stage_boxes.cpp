// mgd.boxes (kBeforeInitialPose). seed 000 Sec. 3.3: Flag_d(x) = 1 for a feature inside a kept
// box (conf > min_confidence, dynamic class). Boxes only: the masks of the detections are not
// used (the paper's YOLO gives boxes). Once tracking runs, in-box features get weight 0 for the
// initial pose (spec E10: relative pose from out-of-box features; mgd.probability sets the real
// weights right after). On the initialisation frame no pose exists yet: every feature gets
// P = P_init(Flag_d), suppressed above tau_dyn, weight 1 - P, so the first keyframe's map points
// carry the box prior.
#include <algorithm>

#include "dynamic/mgd/line_samples.h"
#include "dynamic/mgd/probability.h"
#include "dynamic/mgd/stages.h"

namespace dynref::mgd {

bool InKeptBox(const FrameDetections* det, const MgdOptions& o, float u, float v) {
  if (det == nullptr) return false;
  const double threshold =
      detect::StageThreshold(o.min_confidence, detect::ParseThresholdScale(o.threshold_scale), det->source);
  for (const DetectedInstance& inst : det->instances) {
    if (inst.confidence <= threshold) continue;
    if (std::find(o.dynamic_class_ids.begin(), o.dynamic_class_ids.end(), inst.class_id) == o.dynamic_class_ids.end())
      continue;
    if (u >= inst.x_min && u <= inst.x_max && v >= inst.y_min && v <= inst.y_max) return true;
  }
  return false;
}

namespace {

// A lost frame has no relative pose to restrict to out-of-box features (E10 is about the relative
// pose): relocalisation is an absolute pose against the map, so, as on the initialisation frame,
// each feature carries its box prior, weight 1 - P_init (in-box 0.5: RANSAC and the robust kernel
// sort the people out). Measured on 12 walking runs (reports/mgd_order.md): no effect on runs
// without a lost frame, neutral on one, +5 tracked frames on the other through a changed map
// after the relocalisation, not more inliers in the relocalisation itself.
void WeighLostFrameByBoxPrior(StageContext& ctx, const MgdOptions& o, const MgdState& s) {
  if (o.weight != WeightForm::kOneMinusP) return;
  const Frame& f = ctx.frame.view();
  const double w = o.p_init_box > o.tau_dyn ? 0.0 : KeptWeight(o.p_init_box, o);
  for (size_t i = 0; i < f.N(); ++i) {
    const int fi = static_cast<int>(i);
    if (!s.in_box[i] || f.IsExcluded(fi)) continue;
    ctx.frame.SetWeight(fi, w);
    if (ctx.trace.full_enabled())
      ctx.trace.ProbabilityUpdate("mgd.boxes", trace::EntityKind::kFeature, f.FeatureId(fi),
                                  {{"lost", 1.0}, {"in_box", 1.0}, {"weight", w}}, 0.0, 0.0);
  }
}

}  // namespace

void BoxStage::Run(StageContext& ctx) {
  const MgdOptions& o = RequireOptions(*state_, name());
  const Frame& f = ctx.frame.view();
  MgdState& s = *state_;
  s.frame = f.index;
  s.stamp = f.stamp_text;
  s.in_box.assign(f.N(), 0);
  if (!tally_) tally_ = std::make_unique<DetectionTally>("mgd.boxes", "mgd.probability.min_confidence", o.min_confidence,
                                                         o.threshold_scale);
  if (f.detections != nullptr) {
    const double threshold = tally_->Threshold(*f.detections);
    for (const DetectedInstance& inst : f.detections->instances)
      if (std::find(o.dynamic_class_ids.begin(), o.dynamic_class_ids.end(), inst.class_id) != o.dynamic_class_ids.end())
        tally_->Count(inst.confidence <= threshold);
  }
  int64_t in_box = 0;
  for (size_t i = 0; i < f.N(); ++i) {
    s.in_box[i] = InKeptBox(f.detections, o, f.keys[i].pt.x, f.keys[i].pt.y) ? 1 : 0;
    in_box += s.in_box[i];
  }
  ctx.trace.FrameCount(name(), "in_box", in_box);
  s.line_in_box = LineSampleBoxFlags(f, o);
  if (!ctx.initialised) {  // initialisation frame: the box prior only
    InitialiseLinePriors(ctx, o, s);
    s.prev_frame = f.index;
    s.prev_p.assign(f.N(), -1.0);
    for (size_t i = 0; i < f.N(); ++i) {
      const int fi = static_cast<int>(i);
      if (f.IsExcluded(fi)) continue;
      const double p = s.in_box[i] ? o.p_init_box : o.p_init_free;
      s.prev_p[i] = p;
      // The first P of the feature (issue 32: what the next frame's inheritance reads), its weight.
      if (ctx.trace.full_enabled())
        ctx.trace.ProbabilityUpdate(name(), trace::EntityKind::kFeature, f.FeatureId(fi),
                                    {{"in_box", double(s.in_box[i])},
                                     {"weight", p > o.tau_dyn ? 0.0 : (o.weight == WeightForm::kOneMinusP ? 1.0 - p : f.Weight(fi))}},
                                    p, p);
      if (p > o.tau_dyn) {
        ctx.frame.Exclude(fi, name(), "p-init>tau");
      } else if (o.weight == WeightForm::kOneMinusP) {
        ctx.frame.SetWeight(fi, 1.0 - p);
      }
    }
    return;
  }
  if (ctx.lost) {
    WeighLostFrameByBoxPrior(ctx, o, s);
    return;
  }
  if (o.initial_pose_out_of_box) {
    // Weight carriers (issue 32): the weight 0 the initial pose's residuals carry, as input
    // `weight` with p = 0 (no probability yet; mgd.probability's records follow).
    const bool full = ctx.trace.full_enabled();
    for (size_t i = 0; i < f.N(); ++i)
      if (s.in_box[i] && !f.IsExcluded(static_cast<int>(i))) {
        ctx.frame.SetWeight(static_cast<int>(i), 0.0);
        if (full)
          ctx.trace.ProbabilityUpdate(name(), trace::EntityKind::kFeature, f.FeatureId(static_cast<int>(i)),
                                      {{"initial_pose", 1.0}, {"in_box", 1.0}, {"weight", 0.0}}, 0.0, 0.0);
      }
    // Lines with any sample in a box leave the initial pose too (weight 0; mgd.probability sets
    // the real weight before the local-map search).
    for (size_t i = 0; i < s.line_in_box.size(); ++i)
      if (s.line_in_box[i][0] || s.line_in_box[i][1] || s.line_in_box[i][2]) {
        ctx.frame.SetLineWeight(static_cast<int>(i), 0.0);
        if (full)
          ctx.trace.ProbabilityUpdate(name(), trace::EntityKind::kLineSample,
                                      FrameStructure::LineId(f.index, static_cast<int>(i)),
                                      {{"initial_pose", 1.0}, {"in_box_s", double(s.line_in_box[i][0])}, {"in_box_m", double(s.line_in_box[i][1])},
                                       {"in_box_e", double(s.line_in_box[i][2])}, {"weight", 0.0}},
                                      0.0, 0.0);
      }
  }
}

void BoxStage::Finish(RunEnd& end) {
  if (tally_) tally_->Report(end);
}

}  // namespace dynref::mgd
