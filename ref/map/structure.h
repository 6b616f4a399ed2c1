// Line and plane features of a frame and their map landmarks (seed 000 Sec. 3.2; issue 13).
// The backbone carries them when a method's config has a `structure:` section (ref/structure);
// otherwise every container here stays empty and the point-only backbone is unchanged.
//
// Conventions: a frame line is an undistorted 2-D segment with its normalised homogeneous line
// l (l . (u, v, 1) = signed pixel distance) and three samples s, m, e (start, image midpoint,
// end) back-projected with depth into the camera frame. A map line is a 3-D segment P_s, P_e in
// the world; its pose residuals use P_s, (P_s + P_e) / 2, P_e. A plane is n^T X + d = 0 with n
// unit (camera planes: n towards the camera, d > 0; map planes: world frame).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "features/planes.h"
#include "map/landmark.h"

namespace dynref {

struct FrameLine {
  Eigen::Vector2d s = Eigen::Vector2d::Zero(), e = Eigen::Vector2d::Zero();  // undistorted px
  Eigen::Vector3d l = Eigen::Vector3d::Zero();  // normalised homogeneous line through s, e
  double angle = 0, length = 0;                 // orientation in [0, pi), px
  int group = -1, companion = -1;               // parallel group, companion line index
  std::array<Eigen::Vector3d, 3> X_c{};         // samples s, m, e in the camera frame
  std::array<uint8_t, 3> sample_depth{};        // 1 = the sample's own depth was measured
  bool has_3d = false;  // all three samples placed and collinear in 3-D: may create a map line
};

struct FrameStructure {
  std::vector<FrameLine> lines;
  cv::Mat line_descriptors;             // N x 32 CV_8U (LBD)
  std::vector<int64_t> map_line_ids;    // per line, -1 none
  std::vector<uint8_t> line_outlier;    // set by pose optimisation
  // Per-line weight multiplying the information of its residuals, as Frame::SetWeight for
  // points (a dynamic method's hook, e.g. w = 1 - P of seed 000); copied into the keyframe, so
  // local BA uses it too. Planes are always static (spec 000 step 12): no plane weight.
  std::vector<double> line_weight;
  std::vector<features::PlaneObservation> planes;
  std::vector<int64_t> map_plane_ids;   // per plane, -1 none
  std::vector<uint8_t> plane_outlier;
  cv::Mat plane_labels;                 // CV_16S per pixel plane index, -1 none (overlays)
  bool enabled = false;
  void Reset(size_t n_lines, size_t n_planes);  // sizes the per-feature vectors, clears ids
  // Canonical trace ids (ref/trace/README.md): line i of frame k "l<k>.<i>", plane "pl<k>.<i>".
  static std::string LineId(int frame, int i) { return "l" + std::to_string(frame) + "." + std::to_string(i); }
  static std::string PlaneId(int frame, int i) { return "pl" + std::to_string(frame) + "." + std::to_string(i); }
};

class MapLine {
 public:
  int64_t id = -1;
  Eigen::Vector3d P_s = Eigen::Vector3d::Zero(), P_e = Eigen::Vector3d::Zero();  // world
  cv::Mat descriptor;                   // 1 x 32 LBD of the creating observation
  std::map<int64_t, int> observations;  // keyframe id -> line index in that keyframe
  int64_t first_kf = -1;
  int first_frame = -1;
  int visible = 1, found = 1;           // as MapPoint (tracking statistics)
  bool bad = false;
  int64_t replaced_by = -1;
  LandmarkDynamicState dynamic;
  std::array<Eigen::Vector3d, 3> Samples() const { return {P_s, 0.5 * (P_s + P_e), P_e}; }
  std::string TraceId() const { return "ml" + std::to_string(id); }
};

class MapPlane {
 public:
  int64_t id = -1;
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();  // world, unit
  double d = 0;
  std::map<int64_t, int> observations;  // keyframe id -> plane index in that keyframe
  int64_t first_kf = -1;
  int first_frame = -1;
  int visible = 1, found = 1;
  bool bad = false;
  int64_t replaced_by = -1;
  std::string TraceId() const { return "mpl" + std::to_string(id); }
};

}  // namespace dynref
