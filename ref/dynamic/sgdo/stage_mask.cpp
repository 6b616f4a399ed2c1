// sgdo.mask (kAfterExtraction). seed 001, Sec. 3.2: M = union of prior-dynamic instance masks,
// dilated (spec 001 E3: classes, confidence and kernel not stated). With reject_in_mask = true
// this is the (S) ablation of Fig. 11b: every keypoint in M is rejected.
#include <algorithm>

#include "dynamic/sgdo/stage_common.h"
#include "dynamic/sgdo/stages.h"
#include "io/coco_classes.h"

namespace dynref::sgdo {

const FrameDetections& RequireDetections(const Frame& frame, const std::string& stage) {
  if (frame.detections == nullptr)
    throw InputError("--detections", stage + " needs instance masks for frame " + frame.stamp_text +
                                         " (run with --detections DIR)");
  return *frame.detections;
}

MaskStage::MaskStage(const ParamMap& p, std::shared_ptr<Blackboard> board)
    : board_(std::move(board)), tally_(name(), p) {
  p.RequireKnownKeys({"dynamic_classes", "min_confidence", "threshold_scale", "dilation_kernel_px", "reject_in_mask"});
  options_.dynamic_class_ids = p.GetCocoClassIds("dynamic_classes");
  options_.min_confidence = p.GetDouble("min_confidence");
  options_.dilation_kernel_px = static_cast<int>(p.GetInt("dilation_kernel_px"));
  reject_in_mask_ = p.GetBool("reject_in_mask");
  try {
    options_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage sgdo.mask: " + std::string(e.what()));
  }
}

void MaskStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  const FrameDetections& det = RequireDetections(f, name());
  board_->frame_index = f.index;
  board_->stamp_text = f.stamp_text;
  // min_confidence is the paper's threshold for its detector, mapped to this source (issue 39).
  DynamicMaskOptions frame_options = options_;
  frame_options.min_confidence = tally_.Threshold(det);
  for (const DetectedInstance& inst : det.instances)
    if (std::find(options_.dynamic_class_ids.begin(), options_.dynamic_class_ids.end(), inst.class_id) !=
        options_.dynamic_class_ids.end())
      tally_.Count(inst.confidence < frame_options.min_confidence);
  board_->mask_options = frame_options;
  board_->mask = BuildDynamicMask(det, ctx.camera.width, ctx.camera.height, frame_options);
  board_->static_labels = StaticClassLabels(det, ctx.camera.width, ctx.camera.height, frame_options);
  const DynamicMask& m = board_->mask;

  trace::TraceWriter& tr = ctx.trace;
  for (const DetectedInstance& inst : det.instances) {
    const std::string id = "i" + std::to_string(f.index) + "." + std::to_string(inst.id);
    const bool dynamic = std::find(m.instance_ids.begin(), m.instance_ids.end(), inst.id) != m.instance_ids.end();
    // What the decision is made from (issue 32: `trace verify` recomputes it): the detector's
    // class and confidence; p(dynamic) 1 for an instance of M.
    if (tr.full_enabled())
      tr.ProbabilityUpdate(name(), trace::EntityKind::kInstanceMask, id,
                           tally_.InstanceInputs(inst), 0.0,
                           dynamic ? 1.0 : 0.0);
    tr.Decision(name(), trace::EntityKind::kInstanceMask, id, !dynamic,
                dynamic ? "prior-dynamic:" + inst.class_name
                        : (inst.confidence < frame_options.min_confidence ? "low-confidence" : "static-class"));
  }
  tr.FrameCount(name(), "instances", static_cast<int64_t>(det.instances.size()));
  tr.FrameCount(name(), "dynamic_instances", static_cast<int64_t>(m.instance_ids.size()));
  tr.FrameCount(name(), "mask_px", cv::countNonZero(m.mask));
  int64_t in_mask = 0, rejected = 0;
  for (size_t i = 0; i < f.N(); ++i) {
    const int inst = m.InstanceAt(f.keys[i].pt.x, f.keys[i].pt.y);
    if (inst != 0) ++in_mask;
    if (!reject_in_mask_) continue;
    if (f.IsExcluded(static_cast<int>(i))) continue;
    // The mask look-up the decision rests on (issue 32): the dynamic instance covering the
    // keypoint (0 = outside M); p(dynamic) 1 inside M.
    if (tr.full_enabled())
      tr.ProbabilityUpdate(name(), trace::EntityKind::kFeature, f.FeatureId(static_cast<int>(i)),
                           {{"instance", static_cast<double>(inst)}}, 0.0, inst != 0 ? 1.0 : 0.0);
    if (inst != 0) {
      ctx.frame.Exclude(static_cast<int>(i), name(), "mask");
      ++rejected;
    } else {
      tr.Decision(name(), trace::EntityKind::kFeature, f.FeatureId(static_cast<int>(i)), true, "outside-mask");
    }
  }
  tr.FrameCount(name(), "keys_in_mask", in_mask);
  tr.FrameCount(name(), "rejected", rejected);
}

}  // namespace dynref::sgdo
