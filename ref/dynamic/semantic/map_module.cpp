// semantic.map (map module). seed 002 Sec. 3.3: per keyframe, the pixels with valid depth
// outside M_dyn are back-projected (Eq. (4), camera frame), coloured RGB blended with the class
// colour of a static recognised object (c = (1 - a) rgb + a class colour, "semi-transparent
// mask"), and voxelised per keyframe (not stated: bounds memory; leaf 1 cm = the map's own leaf).
// At the end of the run (spec 002 step 8, proposed) every keyframe cloud is registered with the
// FINAL keyframe pose (Eq. (7)-(8)); the clouds of keyframes local mapping culls are dropped
// (ORB-SLAM2's culling removes keyframes whose points 3 others see: memory stays bounded), then SOR
// (k, 2.5 sigma), voxel grid, OctoMap octree and the floor-aligned 2-D grid; each stage's cloud
// or map is written with its file size in run.json (the paper's file-size table).
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "core/error.h"
#include "dense/filters.h"
#include "dense/octree_export.h"
#include "dense/pcd_io.h"
#include "io/ply.h"
#include "dynamic/semantic/components.h"

namespace dynref::semantic {
namespace {

std::string SizeText(const std::string& path) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(path, ec);
  return ec ? std::string("?") : std::to_string(n) + " bytes";
}

}  // namespace

void MapOptions::Check() const {
  backproject.Check();
  sor.Check();
  if (!(keyframe_leaf_m > 0) || !(voxel_leaf_m > 0) || !(octree_resolution_m > 0) || !(grid.cell_m > 0))
    throw std::invalid_argument("leaf sizes and cell size must be > 0");
  if (!(semantic_alpha >= 0 && semantic_alpha <= 1)) throw std::invalid_argument("semantic_alpha must be in [0, 1]");
  if (!(grid.h_max_m > grid.h_min_m)) throw std::invalid_argument("grid_h_max_m must be > grid_h_min_m");
  if (prefix.empty() || prefix.find('/') != std::string::npos) throw std::invalid_argument("output_prefix must be a file name");
}

MapModule::MapModule(const ParamMap& p, std::shared_ptr<Board> board) : board_(std::move(board)) {
  p.RequireKnownKeys({"min_depth_m", "max_depth_m", "pixel_stride", "keyframe_leaf_m", "semantic_alpha", "sor_k",
                      "sor_std_mult", "voxel_leaf_m", "octree_resolution_m", "grid_cell_m", "grid_h_min_m",
                      "grid_h_max_m", "floor_seed", "remove_dynamic", "write_intermediate", "output_prefix"});
  o_.backproject.min_depth_m = p.GetDouble("min_depth_m");
  o_.backproject.max_depth_m = p.GetDouble("max_depth_m");
  o_.backproject.pixel_stride = static_cast<int>(p.GetInt("pixel_stride"));
  o_.backproject.colour_by_class = false;
  o_.keyframe_leaf_m = p.GetDouble("keyframe_leaf_m");
  o_.semantic_alpha = p.GetDouble("semantic_alpha");
  o_.sor.k = static_cast<int>(p.GetInt("sor_k"));
  o_.sor.std_mult = p.GetDouble("sor_std_mult");
  o_.voxel_leaf_m = p.GetDouble("voxel_leaf_m");
  o_.octree_resolution_m = p.GetDouble("octree_resolution_m");
  o_.grid.cell_m = p.GetDouble("grid_cell_m");
  o_.grid.h_min_m = p.GetDouble("grid_h_min_m");
  o_.grid.h_max_m = p.GetDouble("grid_h_max_m");
  o_.floor.seed = static_cast<uint64_t>(p.GetInt("floor_seed"));
  o_.remove_dynamic = p.GetBool("remove_dynamic");
  o_.write_intermediate = p.GetBool("write_intermediate");
  o_.prefix = p.GetString("output_prefix");
  try {
    o_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "map module semantic.map: " + std::string(e.what()));
  }
}

void MapModule::OnKeyFrame(const MapModuleContext& ctx) {
  const Frame& f = ctx.frame;
  if (!board_->Has(f)) throw std::logic_error("semantic.map needs semantic.mask earlier in the stage list");
  const cv::Mat exclude = o_.remove_dynamic ? board_->dynamic.mask : cv::Mat();
  if (!rays_ready_) rays_ = dense::UndistortedRays(ctx.camera), rays_ready_ = true;
  dense::PointCloud cloud = dense::BackProjectKeyframe(f.rgb, f.depth_m, exclude, board_->static_classes, ctx.camera,
                                                       o_.backproject, rays_, ctx.threads);
  const double a = o_.semantic_alpha;
  for (dense::ColoredPoint& p : cloud) {
    uint8_t r, g, b;
    if (!dense::ClassColour(p.class_id, r, g, b)) continue;
    p.r = static_cast<uint8_t>(std::lround((1 - a) * p.r + a * r));
    p.g = static_cast<uint8_t>(std::lround((1 - a) * p.g + a * g));
    p.b = static_cast<uint8_t>(std::lround((1 - a) * p.b + a * b));
  }
  const int64_t back_projected = static_cast<int64_t>(cloud.size());
  keyframe_clouds_[ctx.keyframe.id] = dense::VoxelDownsample(cloud, o_.keyframe_leaf_m);
  ctx.trace.FrameCount(name(), "back_projected", back_projected);
  ctx.trace.FrameCount(name(), "after_keyframe_voxel", static_cast<int64_t>(keyframe_clouds_[ctx.keyframe.id].size()));
}

void MapModule::OnMapUpdate(const MapModuleContext& ctx) {
  int64_t dropped = 0;
  for (auto it = keyframe_clouds_.begin(); it != keyframe_clouds_.end();) {
    const KeyFrame* kf = ctx.map.kf(it->first);
    if (kf == nullptr || kf->bad) {
      it = keyframe_clouds_.erase(it);
      ++dropped;
    } else {
      ++it;
    }
  }
  ctx.trace.FrameCount(name(), "culled_keyframe_clouds", dropped);
  ctx.trace.FrameCount(name(), "keyframe_clouds", static_cast<int64_t>(keyframe_clouds_.size()));
}

void MapModule::Finish(const Map& map, RunEnd& end) {
  if (keyframe_clouds_.empty() || end.out_dir().empty()) return;
  const std::string base = end.out_dir() + "/" + o_.prefix;
  // Registration with the final poses (keyframe id order).
  dense::PointCloud raw;
  for (const auto& [kf_id, cloud] : keyframe_clouds_) {
    const SE3 T_wc = map.kf(kf_id)->T_cw.inverse();
    for (dense::ColoredPoint p : cloud) {
      const Eigen::Vector3d w = T_wc * Eigen::Vector3d(p.x, p.y, p.z);
      p.x = static_cast<float>(w.x()), p.y = static_cast<float>(w.y()), p.z = static_cast<float>(w.z());
      raw.push_back(p);
    }
  }
  auto report = [&](const std::string& path, const std::string& what) {
    end.AddOutput(name(), path, what + ", " + SizeText(path));
  };
  if (o_.write_intermediate) {
    dense::WritePcd(base + "_raw.pcd", raw);
    report(base + "_raw.pcd", "registered keyframe clouds, " + std::to_string(raw.size()) + " points");
  }
  const dense::PointCloud sor = dense::StatisticalOutlierRemoval(raw, o_.sor);
  if (o_.write_intermediate) {
    dense::WritePcd(base + "_sor.pcd", sor);
    report(base + "_sor.pcd", "after SOR, " + std::to_string(sor.size()) + " points");
  }
  const dense::PointCloud voxel = dense::VoxelDownsample(sor, o_.voxel_leaf_m);
  dense::WritePcd(base + ".pcd", voxel);
  report(base + ".pcd", "after voxel grid, " + std::to_string(voxel.size()) + " points");
  WritePly(base + ".ply", voxel, PlyFormat::kBinaryLittleEndian,
           "dynref semantic map (seed 002 Sec. 3.3)");
  report(base + ".ply", "after voxel grid (PLY), " + std::to_string(voxel.size()) + " points");
  const dense::OctreeStats os = dense::WriteOctrees(voxel, o_.octree_resolution_m, base + ".ot", base + ".bt");
  report(base + ".ot", "OctoMap ColorOcTree, " + std::to_string(os.leaf_nodes) + " leaves, " +
                           std::to_string(os.inner_nodes) + " inner nodes");
  report(base + ".bt", "OctoMap binary OcTree, " + std::to_string(os.occupied_leaves) + " occupied leaves");
  const dense::FloorPlane floor = dense::FitFloor(voxel, o_.floor);
  if (!floor.found) throw std::runtime_error("no floor plane found for the 2-D grid (no near-horizontal plane)");
  const dense::OccupancyGrid grid = dense::BuildOccupancyGrid(voxel, floor, o_.grid);
  dense::WriteMapServer(grid, base + "_grid.pgm", base + "_grid.yaml");
  report(base + "_grid.pgm", "2-D occupancy grid " + std::to_string(grid.width) + " x " + std::to_string(grid.height) +
                                 ", " + std::to_string(grid.occupied_cells) + " occupied cells");
  report(base + "_grid.yaml", "ROS map_server metadata");
}

}  // namespace dynref::semantic
