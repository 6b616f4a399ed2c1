// One RGB-D frame as ORB-SLAM2's Frame (RGB-D constructor): keypoints (raw and undistorted),
// descriptors (rBRIEF or a float plug-in's, issue 17), depth per keypoint, the virtual right coordinate u_R = u_L - bf/z, the
// matched map point per keypoint, and the per-feature method state (exclusion and weight) every
// dynamic method writes through the stage hooks.
//
// Contract (backbone issue 5): an excluded feature is never matched, never used in pose
// optimisation, never creates a map point and never enters local BA. A weight multiplies the
// information of the feature's residual in pose optimisation and is stored on the keyframe
// observation so local BA uses it as well.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/se3.h"
#include "features/descriptor.h"
#include "io/camera.h"
#include "io/mask_format.h"
#include "map/structure.h"

namespace dynref {
namespace trace {
class TraceWriter;
}

// Scale pyramid of the extractor (ORB-SLAM2: nLevels 8, scaleFactor 1.2).
struct ScalePyramid {
  int n_levels = 8;
  double scale_factor = 1.2;
  std::vector<float> scale;          // scale^level
  std::vector<float> inv_scale;
  std::vector<float> sigma2;         // scale^(2 level): ORB-SLAM2 mvLevelSigma2
  std::vector<float> inv_sigma2;
  static ScalePyramid Make(int n_levels, double scale_factor);
};

// Grid cells over the undistorted image bounds for area queries (ORB-SLAM2 FRAME_GRID 64 x 48).
constexpr int kGridCols = 64;
constexpr int kGridRows = 48;

class Frame {
 public:
  int index = -1;               // position in the sequence (0-based)
  double stamp = 0;
  std::string stamp_text;       // as in rgb.txt (key for detections)

  cv::Mat rgb;                  // CV_8UC3 BGR
  cv::Mat grey;                 // CV_8U
  cv::Mat depth_m;              // CV_32F metres, 0 = invalid

  std::vector<cv::KeyPoint> keys;     // as detected (distorted image)
  std::vector<cv::KeyPoint> keys_un;  // undistorted (== keys without distortion)
  cv::Mat descriptors;                // N rows: CV_8U bit strings (ORB: 32 bytes) or CV_32F unit rows
  features::DescriptorProfile match_profile;  // units of the matchers' gates, orientation (extractor)
  std::vector<float> depth;           // metres per key, <= 0 none
  std::vector<float> u_right;         // virtual right u per key, < 0 none
  std::vector<int64_t> map_point_ids; // matched map point per key, -1 none
  std::vector<uint8_t> outlier;       // set by pose optimisation (1 = outlier)

  SE3 T_cw = SE3::Identity();
  bool has_pose = false;

  FrameStructure structure;           // lines and planes (empty unless the config enables them)

  const FrameDetections* detections = nullptr;  // nullable
  const Camera* camera = nullptr;
  ScalePyramid pyramid;
  trace::TraceWriter* trace = nullptr;          // Decision records of Exclude (nullable)

  // Undistorted image bounds (ORB-SLAM2 mnMinX..mnMaxY) and grid.
  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;

  size_t N() const { return keys_un.size(); }

  // ---- per-feature method state ----
  // Marks feature i excluded; logs Decision(stage, kFeature, "f<index>.<i>", kept=false, reason).
  // A matched map point association is removed (and remembered: AssociatedMapPoint). Excluding
  // twice keeps the first reason.
  void Exclude(int i, const std::string& stage, const std::string& reason);
  // Removes feature i's map point association (map_point_ids[i] = -1) and remembers it, so the
  // trace can still name the point the stages saw (OBS associated_map_point_id, trace schema 3).
  // For code that drops an association the stages saw, e.g. a final-optimisation outlier.
  void DropAssociation(int i);
  // The map point feature i is associated with (map_point_ids[i], outlier or not) or, when that
  // is -1, the last one Exclude / DropAssociation removed; -1 when never associated.
  int64_t AssociatedMapPoint(int i) const;
  bool IsExcluded(int i) const { return !excluded_.empty() && excluded_[i] != 0; }
  // Weight in [0, inf) multiplying the information of the feature's residuals (default 1).
  void SetWeight(int i, double w);
  double Weight(int i) const { return weights_.empty() ? 1.0 : weights_[i]; }
  int ExcludedCount() const;
  const std::vector<uint8_t>& excluded_flags() const { return excluded_; }
  const std::vector<double>& weights() const { return weights_; }

  // ---- geometry ----
  // Sizes the per-key vectors, computes depth/u_right from depth_m (ORB-SLAM2
  // ComputeStereoFromRGBD: depth sampled at the raw keypoint) and builds the grid.
  // depth_edge_rel > 0 (backbone key depth_edge_rel; 0 = ORB-SLAM2): a keypoint on a depth
  // discontinuity gets no depth (monocular point), i.e. when a pixel of its 5x5 neighbourhood has
  // no depth or differs from the keypoint's by more than depth_edge_rel * d.
  void FinishFeatures(const Camera& camera, double depth_edge_rel = 0);
  // Camera centre in world coordinates.
  Eigen::Vector3d CameraCentre() const { return T_cw.inverse().translation(); }
  // Back-projection of key i with its depth into the world (requires depth[i] > 0).
  Eigen::Vector3d UnprojectWorld(int i) const;
  bool IsClose(int i) const;  // depth within th_depth baselines (ORB-SLAM2 "close" point)
  // Keys within radius r of (x,y) with octave in [min_level, max_level] (-1 = unbounded),
  // ascending index. Excluded keys are never returned.
  std::vector<int> FeaturesInArea(float x, float y, float r, int min_level = -1,
                                  int max_level = -1) const;
  bool InImage(float u, float v) const { return u >= min_x && u < max_x && v >= min_y && v < max_y; }

  // Canonical trace entity id of feature i: "f<frame>.<i>".
  std::string FeatureId(int i) const;

 private:
  std::vector<uint8_t> excluded_;
  std::vector<double> weights_;
  std::vector<int64_t> dropped_map_point_ids_;  // association removed by Exclude/DropAssociation (-1)
  std::vector<std::vector<int>> grid_;  // kGridCols * kGridRows cells, row-major by column
  float grid_inv_w_ = 0, grid_inv_h_ = 0;
};

}  // namespace dynref
