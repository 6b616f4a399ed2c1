#include "synth/scene_export.h"

#include <algorithm>
#include <cmath>

#include "io/ply.h"

namespace dynref::synth {
namespace {

// 21 bits per axis (+-20 km at 2 cm), packed so that std::set orders keys deterministically.
int64_t VoxelKey(const Eigen::Vector3d& p) {
  const auto cell = [](double v) { return static_cast<int64_t>(std::floor(v / kObservedVoxelM)) + (int64_t{1} << 20); };
  return (cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z());
}

ColoredPoint VoxelCentre(int64_t key, uint8_t r, uint8_t g, uint8_t b) {
  const int64_t mask = (int64_t{1} << 21) - 1;
  const auto centre = [](int64_t c) { return static_cast<float>((static_cast<double>(c - (int64_t{1} << 20)) + 0.5) * kObservedVoxelM); };
  ColoredPoint p;
  p.x = centre((key >> 42) & mask), p.y = centre((key >> 21) & mask), p.z = centre(key & mask);
  p.r = r, p.g = g, p.b = b;
  return p;
}

}  // namespace

void SceneGeometryRecorder::AddFrame(const std::vector<DrawItem>& items, const std::vector<uint8_t>& moving,
                                     const std::set<int>& moving_ids, const cv::Mat& instance_ids,
                                     const cv::Mat& depth_m, const Intrinsics& K, const SE3& T_wc) {
  if (item_ever_moved_.size() < items.size()) item_ever_moved_.resize(items.size(), 0);
  for (size_t k = 0; k < items.size() && k < moving.size(); ++k) item_ever_moved_[k] |= moving[k];
  instances_ever_moved_.insert(moving_ids.begin(), moving_ids.end());
  last_items_ = items;
  std::unordered_set<int64_t>* keys = nullptr;
  int last_instance = -1;
  int64_t last_key = 0;
  for (int y = 0; y < depth_m.rows; y += 2)
    for (int x = 0; x < depth_m.cols; x += 2) {
      const float z = depth_m.at<float>(y, x);
      if (!(z > 0)) continue;
      const Eigen::Vector3d X_c((x - K.cx) * z / K.fx, (y - K.cy) * z / K.fy, z);
      const int instance = instance_ids.at<uint16_t>(y, x);
      const int64_t key = VoxelKey(T_wc * X_c);
      if (instance == last_instance && key == last_key) continue;  // neighbours share a 2 cm voxel
      if (instance != last_instance) keys = &observed_[instance];
      keys->insert(key);
      last_instance = instance, last_key = key;
    }
}

void SceneGeometryRecorder::Write(const std::string& gt_dir) const {
  TriangleMesh mesh;
  for (size_t k = 0; k < last_items_.size(); ++k) {
    if (k < item_ever_moved_.size() && item_ever_moved_[k]) continue;
    const DrawItem& it = last_items_[k];
    const uint32_t base = static_cast<uint32_t>(mesh.vertices.size());
    for (const Eigen::Vector3f& v : it.mesh->pos) {
      const Eigen::Vector3d w = it.T_wo * v.cast<double>();
      mesh.vertices.push_back({static_cast<float>(w.x()), static_cast<float>(w.y()), static_cast<float>(w.z())});
    }
    for (const MeshTri& t : it.mesh->tris)
      mesh.faces.push_back({base + static_cast<uint32_t>(t.a), base + static_cast<uint32_t>(t.b), base + static_cast<uint32_t>(t.c)});
  }
  WritePlyMesh(gt_dir + "/static_scene.ply", mesh,
               "dynref synth: draw items that never move in this sequence, world frame (z up), metres");
  std::vector<int64_t> still, movers;
  for (const auto& [instance, keys] : observed_) {
    std::vector<int64_t>& into = instances_ever_moved_.count(instance) ? movers : still;
    into.insert(into.end(), keys.begin(), keys.end());
  }
  for (std::vector<int64_t>* keys : {&still, &movers}) {  // ascending and unique, as a std::set
    std::sort(keys->begin(), keys->end());
    keys->erase(std::unique(keys->begin(), keys->end()), keys->end());
  }
  PointCloud a, b;
  for (int64_t k : still) a.push_back(VoxelCentre(k, 160, 160, 160));
  for (int64_t k : movers) b.push_back(VoxelCentre(k, 220, 40, 40));
  WritePly(gt_dir + "/static_observed.ply", a, PlyFormat::kBinaryLittleEndian,
           "dynref synth: 2 cm voxel centres of static surfaces seen by the camera (noise-free depth)");
  WritePly(gt_dir + "/movers_observed.ply", b, PlyFormat::kBinaryLittleEndian,
           "dynref synth: 2 cm voxel centres of surfaces of instances that move, at every frame seen");
}

}  // namespace dynref::synth
