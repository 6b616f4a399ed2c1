// blur.mask: seed 003 Sec. 3.1-3.2 (spec 003 steps 1-3). Person masks from the segmenter, the
// missed-segmentation compensation (compensation.h), depth fusion of every person box after
// compensation (depth_fusion.h), then dilation. Every step is traced (README "Trace"): the areas
// behind r per frame, each person's association, each pasted prediction with its history, each
// track that ends, each box's human value range and samples, and the pixel counts by origin.
#include <algorithm>
#include <map>
#include <stdexcept>

#include "core/error.h"
#include "dynamic/blur/components.h"

namespace dynref::blur {

FusedMaskOptions MaskOptionsFromParams(const ParamMap& p) {
  p.RequireKnownKeys({"person_classes", "min_confidence", "threshold_scale", "compensation", "r_threshold", "history", "iou_found",
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
    : o_(MaskOptionsFromParams(p)), board_(std::move(board)), tally_(name(), p) {
  if (p.GetBool("write_mask_layers"))
    layers_ = std::make_unique<MaskLayersWriter>(std::vector<MaskLayer>{{kSegmenter, "segmenter", 255, 64, 64},
                                                                        {kCompensation, "compensation", 255, 200, 0},
                                                                        {kDepthFusion, "depth-fusion", 0, 200, 255},
                                                                        {kDilation, "dilation", 180, 80, 255}});
}

void MaskStage::Finish(RunEnd& end) {
  tally_.Report(end);
  if (!layers_ || end.out_dir().empty()) return;
  const size_t n = layers_->Write(end.out_dir() + "/masks");
  end.AddOutput(name(), end.out_dir() + "/masks", "origin of every M_sd pixel, " + std::to_string(n) +
                                                       " frames (segmenter / compensation / depth-fusion / dilation)");
}

// Trace level full (README "Trace"): every person with its association, every pasted prediction
// with the (x, y, t) history behind its fit, every track that ends, every fused box with its
// samples. Regions (pastes, then fused boxes) are pixel regions r<frame>.<k>; persons are
// instance masks i<frame>.<detection id>.
void MaskStage::TraceMask(trace::TraceWriter& tr, const Frame& f, const FusedMask& m) {
  const std::string fi = std::to_string(f.index);
  const CompensationResult& comp = m.comp;
  std::map<int, std::string> entity_of_track;  // this frame's state of every live track
  for (size_t b = 0; b < m.persons.size(); ++b) {
    const cv::Rect& box = m.persons[b].box;
    const PersonAssociation& as = comp.association[b];
    const std::string id = "i" + fi + "." + std::to_string(m.persons[b].detection_id);
    tr.ProbabilityUpdate("blur.compensation", trace::EntityKind::kInstanceMask, id,
                         {{"track", double(as.track)}, {"found", as.found ? 1.0 : 0.0}, {"iou", as.iou},
                          {"x_min", double(box.x)}, {"y_min", double(box.y)},
                          {"x_max", double(box.br().x - 1)}, {"y_max", double(box.br().y - 1)}, {"t", f.stamp}},
                         1.0, 1.0);  // a segmented person is dynamic (paper Sec. 3.1)
    entity_of_track[as.track] = id;
  }
  int region = 0;
  for (const PastedMask& pm : comp.pasted) {
    std::vector<trace::NamedValue> in = {{"track", double(pm.track)}, {"samples", double(pm.samples)}};
    for (size_t j = 0; j < pm.history.size(); ++j) {
      const std::string k = std::to_string(j);
      in.push_back({"x" + k, pm.history[j].x});
      in.push_back({"y" + k, pm.history[j].y});
      in.push_back({"t" + k, pm.history[j].t});
    }
    in.insert(in.end(), {{"t_c", f.stamp}, {"from_x", pm.from.x}, {"from_y", pm.from.y}, {"to_x", pm.to.x},
                         {"to_y", pm.to.y}, {"dx", double(pm.shift.x)}, {"dy", double(pm.shift.y)},
                         {"x_min", double(pm.box.x)}, {"y_min", double(pm.box.y)},
                         {"x_max", double(pm.box.br().x - 1)}, {"y_max", double(pm.box.br().y - 1)},
                         {"moved_px", double(pm.moved_px)}, {"pasted_px", double(pm.pasted_px)},
                         {"consecutive", double(pm.consecutive)}});
    const std::string id = "r" + fi + "." + std::to_string(region++);
    // Before: not in the segmenter's mask; after: pasted into M_s, dynamic (Sec. 3.1).
    tr.ProbabilityUpdate("blur.compensation", trace::EntityKind::kPixelRegion, id, in, 0.0, 1.0);
    entity_of_track[pm.track] = id;
  }
  static const char* const kWhy[] = {"lost:compensation-off", "lost:not-triggered", "lost:max-consecutive",
                                     "lost:outside-image"};
  for (const DroppedTrack& d : comp.dropped) {
    // The decision names the track's last state (the previous frame's record carrying it).
    const auto it = track_entity_.find(d.track);
    if (it == track_entity_.end()) throw std::logic_error("blur.mask: dropped track without a traced state");
    const trace::EntityKind kind =
        it->second[0] == 'i' ? trace::EntityKind::kInstanceMask : trace::EntityKind::kPixelRegion;
    tr.Decision("blur.compensation", kind, it->second, false, kWhy[d.why]);
  }
  track_entity_ = std::move(entity_of_track);
  for (size_t b = 0; b < m.fusion.size(); ++b) {
    const BoxFusion& bf = m.fusion[b];
    const HumanValueRange& h = bf.range;
    // Geometry inputs x_min..y_max (ref/trace/README.md) so overlays draw the box.
    std::vector<trace::NamedValue> in = {
        {"box", double(b)}, {"x_min", double(bf.box.x)}, {"y_min", double(bf.box.y)},
        {"x_max", double(bf.box.br().x - 1)}, {"y_max", double(bf.box.br().y - 1)}, {"in_box", double(h.in_box)},
        {"samples", double(h.samples)}, {"g_h", h.g_h}, {"lo", h.lo}, {"hi", h.hi}, {"mu_box", h.mu_box},
        {"sigma_box", h.sigma_box}, {"box_valid_px", double(h.box_valid_px)}, {"fused_px", double(h.fused_px)},
        {"added_px", double(bf.added_px)}};
    for (size_t j = 0; j < h.sample_depths.size(); ++j) in.push_back({"d" + std::to_string(j), h.sample_depths[j]});
    // After: the box's M_d^i is dynamic when it holds a pixel (Sec. 3.2).
    tr.ProbabilityUpdate("blur.depth_fusion", trace::EntityKind::kPixelRegion, "r" + fi + "." + std::to_string(region++),
                         in, 0.0, h.fused_px > 0 ? 1.0 : 0.0);
  }
}

void MaskStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  if (f.detections == nullptr)
    throw InputError("--detections", "blur.mask needs person masks for frame " + f.stamp_text + " (run with --detections DIR)");
  if (!builder_) builder_ = std::make_unique<FusedMaskBuilder>(o_, cv::Size(ctx.camera.width, ctx.camera.height));
  const double threshold = tally_.Threshold(*f.detections);
  for (const DetectedInstance& inst : f.detections->instances)
    if (o_.person_class_ids.count(inst.class_id)) tally_.Count(inst.confidence < threshold);
  const FusedMask m = builder_->Build(*f.detections, f.depth_m, f.stamp, "--detections", threshold);
  trace::TraceWriter& tr = ctx.trace;
  if (tr.full_enabled()) TraceMask(tr, f, m);
  Board& board = *board_;
  board.frame = f.index;
  board.stamp = f.stamp_text;
  board.mask = m.mask;
  board.origin = m.origin;
  if (layers_) layers_->Add(f.stamp_text, m.origin);
  tr.FrameCount(name(), "persons", int64_t(m.persons.size()));
  tr.FrameCount(name(), "area_now", int64_t(m.comp.area_now));
  tr.FrameCount(name(), "area_before", int64_t(m.comp.area_before));
  tr.FrameCount(name(), "area_after", int64_t(cv::countNonZero(m.comp.mask)));
  tr.FrameCount(name(), "pasted", int64_t(m.comp.pasted.size()));
  tr.FrameCount(name(), "px_segmenter", cv::countNonZero(m.origin == kSegmenter));
  tr.FrameCount(name(), "px_compensation", cv::countNonZero(m.origin == kCompensation));
  tr.FrameCount(name(), "px_depth_fusion", cv::countNonZero(m.origin == kDepthFusion));
  tr.FrameCount(name(), "px_dilation", cv::countNonZero(m.origin == kDilation));
}

}  // namespace dynref::blur
