// blur.mask: seed 003 Sec. 3.1-3.2 (spec 003 steps 1-3). Person masks from the segmenter, the
// missed-segmentation compensation (compensation.h), depth fusion of every person box after
// compensation (depth_fusion.h), then dilation. Every step is traced: r per frame, each pasted
// prediction, each box's human value range and the pixels it added, and the pixel counts by origin.
#include <algorithm>
#include <stdexcept>

#include "core/error.h"
#include "dynamic/blur/components.h"

namespace dynref::blur {

FusedMaskOptions MaskOptionsFromParams(const ParamMap& p) {
  p.RequireKnownKeys({"person_classes", "min_confidence", "compensation", "r_threshold", "history", "iou_found",
                      "max_consecutive", "depth_fusion", "grid_cols", "grid_rows", "samples_per_cell", "alpha_m",
                      "sigma_mult", "dilation_size", "sampling_seed", "write_mask_layers"});
  FusedMaskOptions o;
  o.person_class_ids.clear();
  for (int id : p.GetCocoClassIds("person_classes")) o.person_class_ids.insert(id);
  o.min_confidence = p.GetDouble("min_confidence");
  o.compensation = p.GetBool("compensation");
  o.comp.r_threshold = p.GetDouble("r_threshold");
  o.comp.history = int(p.GetInt("history"));
  o.comp.iou_found = p.GetDouble("iou_found");
  o.comp.max_consecutive = int(p.GetInt("max_consecutive"));
  o.depth_fusion = p.GetBool("depth_fusion");
  o.depth.grid_cols = int(p.GetInt("grid_cols"));
  o.depth.grid_rows = int(p.GetInt("grid_rows"));
  o.depth.samples_per_cell = int(p.GetInt("samples_per_cell"));
  o.depth.alpha_m = p.GetDouble("alpha_m");
  o.depth.sigma_mult = p.GetDouble("sigma_mult");
  o.dilation_size = int(p.GetInt("dilation_size"));
  o.sampling_seed = uint64_t(p.GetInt("sampling_seed"));
  try {
    o.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage blur.mask: " + std::string(e.what()));
  }
  return o;
}

MaskStage::MaskStage(const ParamMap& p, std::shared_ptr<Board> board)
    : o_(MaskOptionsFromParams(p)), board_(std::move(board)) {
  if (p.GetBool("write_mask_layers"))
    layers_ = std::make_unique<MaskLayersWriter>(std::vector<MaskLayer>{{kSegmenter, "segmenter", 255, 64, 64},
                                                                        {kCompensation, "compensation", 255, 200, 0},
                                                                        {kDepthFusion, "depth-fusion", 0, 200, 255},
                                                                        {kDilation, "dilation", 180, 80, 255}});
}

void MaskStage::Finish(RunEnd& end) {
  if (!layers_ || end.out_dir().empty()) return;
  const size_t n = layers_->Write(end.out_dir() + "/masks");
  end.AddOutput(name(), end.out_dir() + "/masks", "origin of every M_sd pixel, " + std::to_string(n) +
                                                       " frames (segmenter / compensation / depth-fusion / dilation)");
}

void MaskStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  if (f.detections == nullptr)
    throw InputError("--detections", "blur.mask needs person masks for frame " + f.stamp_text + " (run with --detections DIR)");
  if (!builder_) builder_ = std::make_unique<FusedMaskBuilder>(o_, cv::Size(ctx.camera.width, ctx.camera.height));
  const FusedMask m = builder_->Build(*f.detections, f.depth_m, f.stamp, "--detections");
  trace::TraceWriter& tr = ctx.trace;
  const std::string fid = "f" + std::to_string(f.index);
  const CompensationResult& comp = m.comp;
  tr.ProbabilityUpdate("blur.compensation", trace::EntityKind::kFrame, fid,
                       {{"area_now", comp.area_now}, {"area_before", comp.area_before},
                        {"r_threshold", o_.comp.r_threshold}, {"enabled", o_.compensation ? 1.0 : 0.0}},
                       comp.r, comp.triggered ? 1.0 : 0.0);
  for (const PastedMask& pm : comp.pasted)
    tr.ProbabilityUpdate("blur.compensation", trace::EntityKind::kInstanceMask, fid + ".t" + std::to_string(pm.track),
                         {{"samples", double(pm.samples)}, {"from_x", pm.from.x}, {"from_y", pm.from.y},
                          {"to_x", pm.to.x}, {"to_y", pm.to.y}},
                         0.0, double(pm.pasted_px));
  for (size_t b = 0; b < m.fusion.size(); ++b) {
    const BoxFusion& bf = m.fusion[b];
    const HumanValueRange& h = bf.range;
    // Geometry inputs x_min..y_max (ref/trace/README.md) so overlays draw the box.
    tr.ProbabilityUpdate("blur.depth_fusion", trace::EntityKind::kPixelRegion, fid + ".b" + std::to_string(b),
                         {{"x_min", double(bf.box.x)}, {"y_min", double(bf.box.y)},
                          {"x_max", double(bf.box.br().x - 1)}, {"y_max", double(bf.box.br().y - 1)},
                          {"samples", double(h.samples)}, {"g_h", h.g_h}, {"lo", h.lo}, {"hi", h.hi},
                          {"mu_box", h.mu_box}, {"sigma_box", h.sigma_box}, {"fused_px", double(h.fused_px)},
                          {"added_px", double(bf.added_px)}},
                         0.0, double(bf.added_px) / std::max(1, bf.box.area()));  // share of the box added
  }
  Board& board = *board_;
  board.frame = f.index;
  board.stamp = f.stamp_text;
  board.mask = m.mask;
  board.origin = m.origin;
  if (layers_) layers_->Add(f.stamp_text, m.origin);
  tr.FrameCount(name(), "persons", int64_t(m.persons.size()));
  tr.FrameCount(name(), "pasted", int64_t(comp.pasted.size()));
  tr.FrameCount(name(), "px_segmenter", cv::countNonZero(m.origin == kSegmenter));
  tr.FrameCount(name(), "px_compensation", cv::countNonZero(m.origin == kCompensation));
  tr.FrameCount(name(), "px_depth_fusion", cv::countNonZero(m.origin == kDepthFusion));
  tr.FrameCount(name(), "px_dilation", cv::countNonZero(m.origin == kDilation));
}

}  // namespace dynref::blur
