// sgdo.densemap (kOnKeyFrameCreated). seed 001, Sec. 3.6 / Fig. 5: on every new keyframe the
// pixels with valid depth outside M are back-projected, voxelised (v_kf) and appended in world
// coordinates; every N_map keyframes SOR + voxel grid (v_glob) run on the global cloud. The map
// is written as PLY when the stage is destroyed at the end of the run (or by WriteMap()).
#include <cstdio>
#include <iostream>
#include <utility>

#include "dense/ply_writer.h"
#include "dynamic/sgdo/stages.h"

namespace dynref::sgdo {

DenseMapStage::DenseMapStage(const ParamMap& p, std::shared_ptr<Blackboard> board) : board_(std::move(board)) {
  RequireKnownKeys(p, {"keyframe_leaf_m", "global_leaf_m", "filter_every_keyframes", "sor_k",
                       "sor_std_mult", "min_depth_m", "max_depth_m", "pixel_stride",
                       "colour_by_class", "output", "ply_format"});
  options_.keyframe_leaf_m = p.GetDouble("keyframe_leaf_m");
  options_.global_leaf_m = p.GetDouble("global_leaf_m");
  options_.filter_every_keyframes = static_cast<int>(p.GetInt("filter_every_keyframes"));
  options_.sor.k = static_cast<int>(p.GetInt("sor_k"));
  options_.sor.std_mult = p.GetDouble("sor_std_mult");
  options_.min_depth_m = p.GetDouble("min_depth_m");
  options_.max_depth_m = p.GetDouble("max_depth_m");
  options_.pixel_stride = static_cast<int>(p.GetInt("pixel_stride"));
  options_.colour_by_class = p.GetBool("colour_by_class");
  output_path_ = p.GetString("output");
  const std::string fmt = p.GetString("ply_format");
  if (fmt == "ascii") format_ = dense::PlyFormat::kAscii;
  else if (fmt != "binary") throw InputError(p.Get("ply_format").file, p.Get("ply_format").line, "ply_format must be binary|ascii");
  if (output_path_.empty()) throw InputError(p.file, p.line, "sgdo.densemap: output must name a file");
  // A relative output lives in the run folder; a ".." component would let it escape from there
  // (absolute paths are taken as given, but without ".." either).
  for (size_t begin = 0; begin <= output_path_.size();) {
    size_t end = output_path_.find('/', begin);
    if (end == std::string::npos) end = output_path_.size();
    if (output_path_.compare(begin, end - begin, "..") == 0)
      throw InputError(p.Get("output").file, p.Get("output").line,
                       "sgdo.densemap: output must not contain a '..' component: " + output_path_);
    begin = end + 1;
  }
  try {
    options_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage sgdo.densemap: " + std::string(e.what()));
  }
  map_ = std::make_unique<dense::DenseMap>(options_);
}

DenseMapStage::~DenseMapStage() {
  try {
    WriteMap();
  } catch (const std::exception& e) {
    std::cerr << "sgdo.densemap: could not write " << output_path_ << ": " << e.what() << "\n";
  }
}

void DenseMapStage::Run(StageContext& ctx) {
  Frame& f = ctx.frame;
  if (ctx.new_keyframe == nullptr) return;
  if (!board_->Has(f)) throw std::logic_error("sgdo.densemap needs sgdo.mask earlier in the stage list");
  if (!resolved_) {  // a relative `output` lives in the run directory
    const std::string& run_dir = ctx.run_dir;
    if (output_path_[0] != '/') {
      if (!run_dir.empty()) {
        output_path_ = run_dir + "/" + output_path_;
      } else {
        // No run directory (a stage driven outside dynref run): never write into the cwd.
        std::cerr << "sgdo.densemap: no run directory in the stage context; " << output_path_
                  << " is not written (give an absolute output path)\n";
        output_path_.clear();
      }
    }
    resolved_ = true;
  }
  if (output_path_.empty()) tr_no_output_ = true;
  const dense::KeyframeInsertStats st = map_->AddKeyframe(
      f.rgb, f.depth_m, board_->mask.mask, board_->static_labels, ctx.camera,
      ctx.new_keyframe->T_cw.inverse());
  written_ = false;
  trace::TraceWriter& tr = ctx.trace;
  tr.FrameCount(name(), "back_projected", st.back_projected);
  tr.FrameCount(name(), "after_voxel", st.after_voxel);
  tr.FrameCount(name(), "global_filter", st.global_filter_ran ? 1 : 0);
  tr.FrameCount(name(), "sor_removed", st.sor_removed);
  tr.FrameCount(name(), "map_points", st.map_points);
  if (tr_no_output_) tr.FrameCount(name(), "no_output_path", 1);
}

void DenseMapStage::WriteMap() {
  if (written_ || map_ == nullptr || map_->keyframes() == 0 || output_path_.empty()) return;
  map_->Finish();
  dense::WritePly(output_path_, map_->cloud(), format_,
                  "dynref sgdo dense static map (seed 001 Sec. 3.6)\nkeyframes " +
                      std::to_string(map_->keyframes()));
  written_ = true;
}

}  // namespace dynref::sgdo
