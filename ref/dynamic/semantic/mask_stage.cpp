// semantic.mask (kAfterExtraction). seed 002 Sec. 3.1-3.2 (Table 1): instances of prior-dynamic
// classes (person, animals) are dynamic; a prior-static instance touching one (interaction test,
// interaction.h) becomes non-prior dynamic; M_dyn = their union; keypoints in M_dyn are removed.
// Works with synthetic masks and `dynref detect` output (instances need pixel masks for the
// interaction test; box-only instances enter M_dyn as boxes and are never tested).
#include <stdexcept>

#include "core/error.h"
#include "dynamic/semantic/components.h"
#include "dynamic/semantic/interaction.h"
#include "io/coco_classes.h"

namespace dynref::semantic {

void MaskOptions::Check() const {
  if (prior_dynamic_class_ids.empty()) throw std::invalid_argument("prior_dynamic_classes must list a class");
  if (!(min_confidence >= 0 && min_confidence <= 1)) throw std::invalid_argument("min_confidence must be in [0, 1]");
  if (d_max_px < 1 || d_max_px > 50) throw std::invalid_argument("d_max_px must be in 1..50");
  if (!(t_int_m > 0)) throw std::invalid_argument("t_int_m must be > 0");
  if (dilation_kernel_px < 1 || dilation_kernel_px % 2 == 0) throw std::invalid_argument("dilation_kernel_px must be odd and >= 1");
}

MaskOptions MaskOptionsFromParams(const ParamMap& p) {
  p.RequireKnownKeys({"prior_dynamic_classes", "min_confidence", "threshold_scale", "d_max_px", "t_int_m", "interaction",
                      "dilation_kernel_px", "reject_keypoints"});
  MaskOptions o;
  for (int id : p.GetCocoClassIds("prior_dynamic_classes")) o.prior_dynamic_class_ids.insert(id);
  o.min_confidence = p.GetDouble("min_confidence");
  o.d_max_px = static_cast<int>(p.GetInt("d_max_px"));
  o.t_int_m = p.GetDouble("t_int_m");
  o.interaction = p.GetBool("interaction");
  o.dilation_kernel_px = static_cast<int>(p.GetInt("dilation_kernel_px"));
  o.reject_keypoints = p.GetBool("reject_keypoints");
  try {
    o.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage semantic.mask: " + std::string(e.what()));
  }
  return o;
}

MaskStage::MaskStage(const ParamMap& p, std::shared_ptr<Board> board)
    : o_(MaskOptionsFromParams(p)), board_(std::move(board)), tally_(name(), p) {}

InstanceClasses ClassifyInstances(const FrameDetections& det, const cv::Mat& depth_m, const MaskOptions& o) {
  InstanceClasses c;
  for (const DetectedInstance& inst : det.instances) {  // ascending id
    if (inst.confidence < o.min_confidence || inst.class_id < 0) continue;
    (o.prior_dynamic_class_ids.count(inst.class_id) ? c.prior_dynamic : c.prior_static).insert(inst.id);
  }
  if (!o.interaction || det.instance_ids.empty() || c.prior_dynamic.empty()) return c;
  const std::map<int, cv::Rect> bounds = InstanceBounds(det.instance_ids);
  for (int b : c.prior_static)
    for (int a : c.prior_dynamic) {
      const InteractionResult r = TestInteraction(det.instance_ids, depth_m, bounds, a, b, o.d_max_px, o.t_int_m);
      if (r.pairs == 0) continue;  // not adjacent: no test
      c.tests.push_back({a, b, r});
      if (r.interacting) {
        c.non_prior_dynamic.insert(b);
        break;  // one interacting prior-dynamic instance is enough
      }
    }
  return c;
}

void MaskStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  if (f.detections == nullptr)
    throw InputError("--detections", "semantic.mask needs instance masks for frame " + f.stamp_text + " (run with --detections DIR)");
  const FrameDetections& det = *f.detections;
  trace::TraceWriter& tr = ctx.trace;
  // min_confidence is the paper's threshold for its detector, mapped to this source (issue 39).
  MaskOptions frame_options = o_;
  frame_options.min_confidence = tally_.Threshold(det);
  for (const DetectedInstance& inst : det.instances)
    if (o_.prior_dynamic_class_ids.count(inst.class_id)) tally_.Count(inst.confidence < frame_options.min_confidence);
  const InstanceClasses classes = ClassifyInstances(det, f.depth_m, frame_options);
  for (const InstanceClasses::Test& t : classes.tests) {
    const InteractionResult& r = t.result;
    const std::string id = "i" + std::to_string(f.index) + "." + std::to_string(t.b);
    tr.ProbabilityUpdate("semantic.interaction", trace::EntityKind::kInstanceMask, id,
                         {{"with_instance", double(t.a)}, {"pairs", double(r.pairs)}, {"dz_mean_m", r.dz_mean_m},
                          {"t_int_m", o_.t_int_m}, {"d_max_px", double(o_.d_max_px)}},
                         0.0, r.interacting ? 1.0 : 0.0);
  }
  const std::set<int>& prior_dynamic = classes.prior_dynamic;
  const std::set<int>& static_ids = classes.prior_static;
  std::set<int> dynamic_ids = prior_dynamic;
  dynamic_ids.insert(classes.non_prior_dynamic.begin(), classes.non_prior_dynamic.end());
  const int64_t tests = static_cast<int64_t>(classes.tests.size());
  const int64_t non_prior = static_cast<int64_t>(classes.non_prior_dynamic.size());
  for (const DetectedInstance& inst : det.instances) {
    const bool dyn = dynamic_ids.count(inst.id) > 0;
    const std::string id = "i" + std::to_string(f.index) + "." + std::to_string(inst.id);
    // What the class partition reads (issue 32: `trace verify` recomputes it): the detector's
    // class and confidence, for every detected instance; p(dynamic) 1 for an instance of M_dyn.
    if (tr.full_enabled())
      tr.ProbabilityUpdate(name(), trace::EntityKind::kInstanceMask, id,
                           tally_.InstanceInputs(inst), 0.0,
                           dyn ? 1.0 : 0.0);
    if (!dyn && !static_ids.count(inst.id)) continue;
    tr.Decision(name(), trace::EntityKind::kInstanceMask, id,
                !dyn, prior_dynamic.count(inst.id) ? "prior-dynamic:" + inst.class_name
                                                    : (dyn ? "non-prior-dynamic:" + inst.class_name : "static:" + inst.class_name));
  }
  Board& b = *board_;
  b.frame = f.index;
  b.stamp = f.stamp_text;
  b.dynamic = geometry::BuildInstanceMask(det, ctx.camera.width, ctx.camera.height, dynamic_ids, o_.dilation_kernel_px);
  b.static_classes = cv::Mat(ctx.camera.height, ctx.camera.width, CV_16S, cv::Scalar(-1));
  for (const DetectedInstance& inst : det.instances)
    if (static_ids.count(inst.id) && !dynamic_ids.count(inst.id) && inst.has_mask)
      b.static_classes.setTo(cv::Scalar(inst.class_id), det.MaskOf(inst.id));
  int64_t removed = 0;
  if (o_.reject_keypoints) {
    for (size_t i = 0; i < f.N(); ++i) {
      const int fi = static_cast<int>(i);
      if (f.IsExcluded(fi)) continue;
      const int inst = b.dynamic.InstanceAt(f.keys[i].pt.x, f.keys[i].pt.y);
      if (inst == 0) continue;  // DynamicMask::InMask
      // The mask look-up the removal rests on (issue 32): the instance of M_dyn at the keypoint.
      if (tr.full_enabled())
        tr.ProbabilityUpdate(name(), trace::EntityKind::kFeature, f.FeatureId(fi), {{"instance", static_cast<double>(inst)}},
                             0.0, 1.0);
      ctx.frame.Exclude(fi, name(), "dynamic-mask");
      ++removed;
    }
  }
  tr.FrameCount(name(), "prior_dynamic", static_cast<int64_t>(prior_dynamic.size()));
  tr.FrameCount(name(), "interaction_tests", tests);
  tr.FrameCount(name(), "non_prior_dynamic", non_prior);
  tr.FrameCount(name(), "mask_px", cv::countNonZero(b.dynamic.mask));
  tr.FrameCount(name(), "keypoints_removed", removed);
}

}  // namespace dynref::semantic
