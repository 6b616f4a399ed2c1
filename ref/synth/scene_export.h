// Ground truth of the scene's geometry for map evaluation (`dynref map-eval`, issue 16), written
// by `dynref synth` into gt/:
//   static_scene.ply     triangle mesh (world frame) of every draw item that never moves in the
//                        sequence: room, furniture, chairs nobody moves;
//   static_observed.ply  2 cm voxel centres of the static surfaces the camera saw (noise-free
//                        G-buffer depth, every 2nd pixel of every frame): what a map can complete;
//   movers_observed.ply  2 cm voxel centres of every surface of an instance that moves at some
//                        frame, at every frame the camera saw it: where ghosts of movers lie.
// "Moves" is the synthetic motion flag of gt/moving.txt (> 1 mm since the previous frame).
#pragma once
#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include "synth/raster.h"
#include "synth/world.h"

namespace dynref::synth {

constexpr double kObservedVoxelM = 0.02;

class SceneGeometryRecorder {
 public:
  explicit SceneGeometryRecorder(const World& world) : world_(world) {}
  // One frame: the draw items at t with their motion flags, and the G-buffer's instance id and
  // camera-frame depth per pixel (CV_16U, CV_32F; depth 0 = nothing).
  void AddFrame(const std::vector<DrawItem>& items, const std::vector<uint8_t>& moving, const std::set<int>& moving_ids,
                const cv::Mat& instance_ids, const cv::Mat& depth_m, const Intrinsics& K, const SE3& T_wc);
  // Writes the three files into gt_dir (atomically each).
  void Write(const std::string& gt_dir) const;

 private:
  const World& world_;
  std::vector<DrawItem> last_items_;
  std::vector<uint8_t> item_ever_moved_;
  std::set<int> instances_ever_moved_;
  // instance -> voxel keys; hashed (a std::set insert per sampled pixel was 7 % of synth's time),
  // sorted when written.
  std::map<int, std::unordered_set<int64_t>> observed_;
};

}  // namespace dynref::synth
