// The keyframe dense static map as a map module; see dense_map_module.h.
#include "dynamic/common/dense_map_module.h"

#include <stdexcept>
#include <utility>

#include "core/error.h"

namespace dynref::dynamic_common {

// Leaf sizes >= 1 mm (a voxel per pixel already below); the context margin's neighbour search
// degenerates to all pairs as it grows (1.5 m: > 120 s for 2 frames, issue 37): at most 0.2 m.
void RegisterDenseMapParams(MethodRegistry& registry, const std::string& module, const std::string& mask_stage) {
  registry.AddParams(
      module,
      {{Real("keyframe_leaf_m", 0.001, 1), Real("global_leaf_m", 0.001, 1), Integer("filter_every_keyframes", 1, 100000),
        Choice("filter_mode", {"full", "incremental"}), RealAbove("context_margin_m", 0, 0.2), Integer("sor_k", 1, 1000),
        RealAbove("sor_std_mult", 0, 100), Real("min_depth_m", 0, 100), RealAbove("max_depth_m", 0, 100),
        Integer("pixel_stride", 1, 64), Flag("colour_by_class"), Text("output"), Choice("ply_format", {"binary", "ascii"})},
       {{"min_depth_m", "max_depth_m"}}});
  registry.AddRequirement(module, mask_stage);
}

DenseMapModule::DenseMapModule(std::string name, std::string ply_comment, const ParamMap& p, KeyframeMaskSource masks)
    : name_(std::move(name)), ply_comment_(std::move(ply_comment)), masks_(std::move(masks)) {
  p.RequireKnownKeys({"keyframe_leaf_m", "global_leaf_m", "filter_every_keyframes", "sor_k",
                      "sor_std_mult", "min_depth_m", "max_depth_m", "pixel_stride",
                      "colour_by_class", "output", "ply_format", "filter_mode", "context_margin_m"});
  options_.keyframe_leaf_m = p.GetDouble("keyframe_leaf_m");
  options_.global_leaf_m = p.GetDouble("global_leaf_m");
  options_.filter_every_keyframes = static_cast<int>(p.GetInt("filter_every_keyframes"));
  options_.sor.k = static_cast<int>(p.GetInt("sor_k"));
  options_.sor.std_mult = p.GetDouble("sor_std_mult");
  options_.min_depth_m = p.GetDouble("min_depth_m");
  options_.max_depth_m = p.GetDouble("max_depth_m");
  options_.pixel_stride = static_cast<int>(p.GetInt("pixel_stride"));
  options_.colour_by_class = p.GetBool("colour_by_class");
  const std::string mode = p.GetString("filter_mode");
  if (mode != "full" && mode != "incremental")
    throw InputError(p.Get("filter_mode").file, p.Get("filter_mode").line, "filter_mode must be full|incremental");
  options_.incremental = mode == "incremental";
  options_.context_margin_m = p.GetDouble("context_margin_m");
  output_ = p.GetString("output");
  const std::string fmt = p.GetString("ply_format");
  if (fmt == "ascii") format_ = PlyFormat::kAscii;
  else if (fmt != "binary") throw InputError(p.Get("ply_format").file, p.Get("ply_format").line, "ply_format must be binary|ascii");
  if (output_.empty()) throw InputError(p.file, p.line, name_ + ": output must name a file");
  // A relative output lives in the run folder; a ".." component would let it escape from there
  // (absolute paths are taken as given, but without ".." either).
  for (size_t begin = 0; begin <= output_.size();) {
    size_t end = output_.find('/', begin);
    if (end == std::string::npos) end = output_.size();
    if (output_.compare(begin, end - begin, "..") == 0)
      throw InputError(p.Get("output").file, p.Get("output").line,
                       name_ + ": output must not contain a '..' component: " + output_);
    begin = end + 1;
  }
  try {
    options_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage " + name_ + ": " + std::string(e.what()));
  }
  map_ = std::make_unique<dense::DenseMap>(options_);
}

void DenseMapModule::OnKeyFrame(const MapModuleContext& ctx) {
  const Frame& f = ctx.frame;
  const KeyframeMasks m = masks_(f);
  map_->set_threads(ctx.threads);
  const dense::KeyframeInsertStats st =
      map_->AddKeyframe(f.rgb, f.depth_m, m.exclude, m.class_labels, ctx.camera, ctx.keyframe.T_cw.inverse());
  trace::TraceWriter& tr = ctx.trace;
  tr.FrameCount(name(), "back_projected", st.back_projected);
  tr.FrameCount(name(), "after_voxel", st.after_voxel);
  tr.FrameCount(name(), "global_filter", st.global_filter_ran ? 1 : 0);
  tr.FrameCount(name(), "sor_removed", st.sor_removed);
  tr.FrameCount(name(), "map_points", st.map_points);
}

void DenseMapModule::Finish(const Map&, RunEnd& end) {
  if (map_->keyframes() == 0) return;
  // Driven outside `dynref run` (no run folder), a relative output is never written into the cwd.
  if (output_[0] != '/' && end.out_dir().empty()) return;
  const std::string path = output_[0] == '/' ? output_ : end.out_dir() + "/" + output_;
  map_->Finish();
  WritePly(path, map_->cloud(), format_, ply_comment_ + "\nkeyframes " + std::to_string(map_->keyframes()));
  end.AddOutput(name(), path, "dense static map, " + std::to_string(map_->cloud().size()) + " points (PLY)");
}

}  // namespace dynref::dynamic_common
