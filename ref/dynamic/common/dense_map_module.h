// The keyframe dense static map as a map module, shared by the methods whose papers build one:
// sgdo.densemap (seed 001 Sec. 3.6, Fig. 5) and blur.densemap (seed 003 Sec. 4.4, spec 003 step
// 7). On every new keyframe the pixels with valid depth outside the method's dynamic mask are
// back-projected, voxelised (v_kf) and appended in world coordinates; every N_map keyframes SOR +
// voxel grid (v_glob) run on the global cloud (filter_mode full) or on the points added since the
// last filter with the map around them as neighbours (filter_mode incremental, dense/dense_map.h:
// cost flat in map size, issue 18). The map is written as PLY into the run folder by Finish; a
// failed write ends the run with an error in run.json.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "dense/dense_map.h"
#include "io/ply.h"
#include "method/map_module.h"
#include "method/registry.h"

namespace dynref::dynamic_common {

// The masks of the keyframe being inserted: exclude CV_8U (non-zero = dynamic) and class labels
// CV_16S (-1 none) or empty. The source throws std::logic_error when the method's mask stage did
// not run on that frame.
struct KeyframeMasks {
  cv::Mat exclude, class_labels;
};
using KeyframeMaskSource = std::function<KeyframeMasks(const Frame&)>;

// The module's keys and ranges (checked before any component is built); `module` needs
// `mask_stage` earlier in the stage list.
void RegisterDenseMapParams(MethodRegistry& registry, const std::string& module, const std::string& mask_stage);

class DenseMapModule : public MapModule {
 public:
  // `name`: the module's config name; `ply_comment`: the PLY header's first comment line.
  DenseMapModule(std::string name, std::string ply_comment, const ParamMap& params, KeyframeMaskSource masks);
  std::string name() const override { return name_; }
  void OnKeyFrame(const MapModuleContext& ctx) override;
  // Final filter + atomic PLY write into the run folder (nothing when no keyframe was added).
  void Finish(const Map& map, RunEnd& end) override;

 private:
  std::string name_, ply_comment_;
  KeyframeMaskSource masks_;
  dense::DenseMapOptions options_;
  std::string output_;  // relative to the run folder, or absolute
  PlyFormat format_ = PlyFormat::kBinaryLittleEndian;
  std::unique_ptr<dense::DenseMap> map_;
};

}  // namespace dynref::dynamic_common
