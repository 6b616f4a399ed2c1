// Dense static point-cloud map built on keyframes (seed 001, Sec. 3.6, Fig. 5):
//   per new keyframe: back-project every pixel with valid depth that is not in the dynamic mask,
//   colour = RGB (recognised static objects optionally recoloured by class, spec 001 E10),
//   single-frame voxel downsample (leaf keyframe_leaf_m), transform to world, append;
//   every `filter_every_keyframes` keyframes: SOR then voxel grid (global_leaf_m) on the whole map
//   (`incremental` = false, the paper's reading), or (`incremental` = true, issue 18) on the
//   points added since the last filter only, merged into global-leaf voxels as they arrive:
//   voxels the map holds or touches join it, the others are judged by SOR (neighbour distances
//   capped at context_margin_m, threshold from the map's and the judged voxels' distribution;
//   the first keyframe seeds the map by plain SOR); accepted voxels are accumulated into a
//   global voxel grid that is never re-voxelised: cost per filter proportional to the new
//   points, flat in map size.
// Keyframe poses are taken as given at insertion (the paper's online mapping thread); later BA
// corrections are not re-applied.
#pragma once
#include <opencv2/core.hpp>
#include <string>

#include "core/se3.h"
#include "dense/filters.h"
#include "dense/point_cloud.h"
#include "dense/voxel_bricks.h"
#include "io/camera.h"

namespace dynref::dense {

struct DenseMapOptions {
  double keyframe_leaf_m = 0.01;   // v_kf, not stated (spec 001 (c))
  double global_leaf_m = 0.01;     // v_glob, not stated
  int filter_every_keyframes = 10; // N_map, not stated ("cumulative number of frames")
  SorOptions sor;                  // k_sor = 50, std_mult = 1.0 (PCL tutorial)
  double min_depth_m = 0.1;        // not stated: below the Kinect minimum range
  double max_depth_m = 6.0;        // not stated: Kinect noise grows ~z^2, TUM scenes < 6 m
  int pixel_stride = 1;            // 1 = every pixel (paper); > 1 only for fast tests
  bool colour_by_class = true;     // Fig. 8c: monitor green, chair red (E10)
  bool final_filter = true;        // one SOR + voxel pass at Finish() if keyframes were added
  bool incremental = false;        // filter new points only (see above)
  double context_margin_m = 0.03;  // incremental: SOR neighbour distances capped here (neighbours looked up within it)
  void Check() const;
};

// Colour of a recognised static class: tv/monitor green, chair red (Fig. 8c); other classes a
// fixed palette by id. Returns false for class_id < 0.
bool ClassColour(int class_id, uint8_t& r, uint8_t& g, uint8_t& b);

// One keyframe's cloud in the CAMERA frame, before voxelisation. bgr CV_8UC3, depth CV_32F m,
// exclude CV_8U (non-zero = dynamic, skipped) or empty, class_labels CV_16S (-1 none) or empty.
// Raw pixel (u, v) is back-projected along its undistorted ray: rays(v, u) = (x, y) with
// P = z (x, y, 1) (UndistortedRays); without distortion (empty rays) the pinhole model.
// threads (the run's --threads): bands of rows side by side, concatenated in row order (the same
// cloud for any count).
PointCloud BackProjectKeyframe(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& exclude,
                               const cv::Mat& class_labels, const Camera& camera,
                               const DenseMapOptions& options, const cv::Mat& rays = cv::Mat(), int threads = 1);

// CV_64FC2 normalised undistorted coordinates of every raw pixel (cv::undistortPoints, once per
// camera); empty when the camera has no distortion (issue 21 defect 4: TUM fr1/fr2).
cv::Mat UndistortedRays(const Camera& camera);

struct KeyframeInsertStats {
  int64_t back_projected = 0;
  int64_t after_voxel = 0;
  int64_t map_points = 0;
  bool global_filter_ran = false;
  int64_t sor_removed = 0;
};

class DenseMap {
 public:
  explicit DenseMap(const DenseMapOptions& options);
  KeyframeInsertStats AddKeyframe(const cv::Mat& bgr, const cv::Mat& depth_m,
                                  const cv::Mat& exclude, const cv::Mat& class_labels,
                                  const Camera& camera, const SE3& T_wc);
  // Final filter (if enabled and keyframes were added since the last one). Returns SOR removals.
  int64_t Finish();
  // The map. Incremental mode: complete only after Finish() (the grid is not copied out per keyframe).
  const PointCloud& cloud() const { return cloud_; }
  int keyframes() const { return keyframes_; }
  // The run's --threads for back-projection and the incremental filter's neighbour statistics;
  // the map is the same bytes for any count.
  void set_threads(int threads) { threads_ = threads; }

 private:
  int64_t FilterGlobal();
  int64_t FilterBatch();  // incremental mode
  bool TouchesMap(const VoxelKey& voxel) const;  // a map voxel in its 26-neighbourhood
  void MergeIntoMap(const VoxelKey& key, const VoxelAccumulator& points);
  // Capped SOR statistic of the judged batch voxels (empty: too few points to judge).
  std::vector<double> JudgedStatistic(const SortedVoxels& batch, const std::vector<uint32_t>& judged) const;
  DenseMapOptions options_;
  VoxelGrid grid_;          // incremental mode: the global map
  PointCloud pending_;      // incremental mode: world points since the last filter
  VoxelBricks bricks_;      // incremental mode: grid_'s centroids for the SOR look-ups
  SorStatistics accepted_stats_;    // statistic of the judged voxels the map kept
  cv::Mat rays_;  // UndistortedRays of the run's camera (empty: no distortion)
  bool rays_ready_ = false;
  PointCloud cloud_;
  int keyframes_ = 0;
  int since_filter_ = 0;
  int threads_ = 1;
};

}  // namespace dynref::dense
