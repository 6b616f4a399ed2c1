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

MaskStage::MaskStage(const ParamMap& p, std::shared_ptr<Board> board) : board_(std::move(board)) {
  p.RequireKnownKeys({"prior_dynamic_classes", "min_confidence", "d_max_px", "t_int_m", "interaction",
                      "dilation_kernel_px", "reject_keypoints"});
  for (int id : p.GetCocoClassIds("prior_dynamic_classes")) o_.prior_dynamic_class_ids.insert(id);
  o_.min_confidence = p.GetDouble("min_confidence");
  o_.d_max_px = static_cast<int>(p.GetInt("d_max_px"));
  o_.t_int_m = p.GetDouble("t_int_m");
  o_.interaction = p.GetBool("interaction");
  o_.dilation_kernel_px = static_cast<int>(p.GetInt("dilation_kernel_px"));
  o_.reject_keypoints = p.GetBool("reject_keypoints");
  try {
    o_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage semantic.mask: " + std::string(e.what()));
  }
}

void MaskStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  if (f.detections == nullptr)
    throw InputError("--detections", "semantic.mask needs instance masks for frame " + f.stamp_text + " (run with --detections DIR)");
  const FrameDetections& det = *f.detections;
  trace::TraceWriter& tr = ctx.trace;
  std::set<int> dynamic_ids, static_ids;
  for (const DetectedInstance& inst : det.instances) {  // ascending id
    if (inst.confidence < o_.min_confidence || inst.class_id < 0) continue;
    (o_.prior_dynamic_class_ids.count(inst.class_id) ? dynamic_ids : static_ids).insert(inst.id);
  }
  const std::set<int> prior_dynamic = dynamic_ids;
  int64_t tests = 0, non_prior = 0;
  if (o_.interaction && !det.instance_ids.empty() && !prior_dynamic.empty()) {
    const std::map<int, cv::Rect> bounds = InstanceBounds(det.instance_ids);
    for (int b : static_ids) {
      for (int a : prior_dynamic) {
        const InteractionResult r = TestInteraction(det.instance_ids, f.depth_m, bounds, a, b, o_.d_max_px, o_.t_int_m);
        if (r.pairs == 0) continue;  // not adjacent: no test
        ++tests;
        const std::string id = "i" + std::to_string(f.index) + "." + std::to_string(b);
        tr.ProbabilityUpdate("semantic.interaction", trace::EntityKind::kInstanceMask, id,
                             {{"with_instance", double(a)}, {"pairs", double(r.pairs)}, {"dz_mean_m", r.dz_mean_m},
                              {"t_int_m", o_.t_int_m}, {"d_max_px", double(o_.d_max_px)}},
                             0.0, r.interacting ? 1.0 : 0.0);
        if (r.interacting) {
          dynamic_ids.insert(b);
          ++non_prior;
          break;  // one interacting prior-dynamic instance is enough
        }
      }
    }
  }
  for (const DetectedInstance& inst : det.instances) {
    if (!dynamic_ids.count(inst.id) && !static_ids.count(inst.id)) continue;
    const bool dyn = dynamic_ids.count(inst.id) > 0;
    tr.Decision(name(), trace::EntityKind::kInstanceMask, "i" + std::to_string(f.index) + "." + std::to_string(inst.id),
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
      if (f.IsExcluded(fi) || !b.dynamic.InMask(f.keys[i].pt.x, f.keys[i].pt.y)) continue;
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
