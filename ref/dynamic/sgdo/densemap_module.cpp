// sgdo.densemap (map module, OnKeyFrame). seed 001, Sec. 3.6 / Fig. 5: on every new keyframe
// the pixels with valid depth outside M are back-projected, voxelised (v_kf) and appended in
// world coordinates; every N_map keyframes SOR + voxel grid (v_glob) run on the global cloud
// (filter_mode full) or on the points added since the last filter with the map around them as
// neighbours (filter_mode incremental, dense/dense_map.h: cost flat in map size, issue 18). The
// map is written as PLY into the run folder by Finish at the end of the run; a failed write ends
// the run with an error in run.json.
#include <utility>

#include "io/ply.h"
#include "dynamic/sgdo/stages.h"

namespace dynref::sgdo {

DenseMapModule::DenseMapModule(const ParamMap& p, std::shared_ptr<Blackboard> board) : board_(std::move(board)) {
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
  if (output_.empty()) throw InputError(p.file, p.line, "sgdo.densemap: output must name a file");
  // A relative output lives in the run folder; a ".." component would let it escape from there
  // (absolute paths are taken as given, but without ".." either).
  for (size_t begin = 0; begin <= output_.size();) {
    size_t end = output_.find('/', begin);
    if (end == std::string::npos) end = output_.size();
    if (output_.compare(begin, end - begin, "..") == 0)
      throw InputError(p.Get("output").file, p.Get("output").line,
                       "sgdo.densemap: output must not contain a '..' component: " + output_);
    begin = end + 1;
  }
  try {
    options_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage sgdo.densemap: " + std::string(e.what()));
  }
  map_ = std::make_unique<dense::DenseMap>(options_);
}

void DenseMapModule::OnKeyFrame(const MapModuleContext& ctx) {
  const Frame& f = ctx.frame;
  if (!board_->Has(f)) throw std::logic_error("sgdo.densemap needs sgdo.mask earlier in the stage list");
  map_->set_threads(ctx.threads);
  const dense::KeyframeInsertStats st = map_->AddKeyframe(
      f.rgb, f.depth_m, board_->mask.mask, board_->static_labels, ctx.camera, ctx.keyframe.T_cw.inverse());
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
  WritePly(path, map_->cloud(), format_,
           "dynref sgdo dense static map (seed 001 Sec. 3.6)\nkeyframes " + std::to_string(map_->keyframes()));
  end.AddOutput(name(), path, "dense static map, " + std::to_string(map_->cloud().size()) + " points (PLY)");
}

}  // namespace dynref::sgdo
