// NeRF-ready export of seed 004 (Sec. 3.3.2, spec 004 step 7): dynref does not train a NeRF; it
// hands over what the paper's NeRF thread trains on.
//   - per keyframe k and its reference r (the previous exported keyframe): static matches (MNN2 on
//     the keypoints left after Module C), linear (DLT) triangulation, kept when the rays have
//     parallax (cos < 0.9998, ORB-SLAM's test), the point lies in front of both cameras and
//     reprojects within tau_rep = sqrt(5.991) px in both views (spec 004 (c) proposals);
//   - the pseudo-point cloud {X_j, c_j}, c_j = the colour of k's image at the observed keypoint;
//   - L_geo = (1/N) sum_j ||I(pi(X_j)) - c_j||^2 (RGB in [0, 1]), over both views of every point;
//   - transforms.json in the nerfstudio / instant-ngp convention: intrinsics, per frame the
//     camera-to-world matrix with OpenGL camera axes (x right, y up, z backwards: the OpenCV
//     camera's y and z negated), the image path and a mask (255 = static pixel, 0 = dynamic: the
//     masks Module C voted dynamic), plus the sparse points (ply_file_path).
#pragma once
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <limits>
#include <string>
#include <vector>

#include "core/se3.h"
#include "io/camera.h"

namespace dynref::epi {

struct TriangulationGates {
  double parallax_cos_max = 0.9998;    // spec 004 (c): ORB-SLAM's cos(parallax) < 0.9998
  double reprojection_px = 2.447651936;  // spec 004 (c): tau_rep = sqrt(5.991) (chi2, 2 dof, 95 %)
  void Check() const;  // std::invalid_argument naming the field
};

enum class Triangulated { kOk = 0, kParallax = 1, kBehind = 2, kReprojection = 3, kDegenerate = 4 };
const char* TriangulatedName(Triangulated t);

// What the gates saw (the epi.nerf trace records; NaN where a gate was not reached).
struct TriangulationValues {
  double cos_parallax = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector3d X = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  // world
  double z0 = std::numeric_limits<double>::quiet_NaN(), z1 = z0;    // depth in each camera
  double err0 = std::numeric_limits<double>::quiet_NaN(), err1 = err0;  // reprojection error (px)
};

// Linear triangulation (geometry/triangulation.h) of undistorted pixels x0, x1 seen from the
// world-to-camera poses T_cw0, T_cw1 through the pinhole K, then the gates. `values` (optional)
// receives what the gates tested.
Triangulated TriangulateDlt(const Intrinsics& K, const SE3& T_cw0, const SE3& T_cw1, const Eigen::Vector2d& x0,
                            const Eigen::Vector2d& x1, const TriangulationGates& gates, Eigen::Vector3d* X,
                            TriangulationValues* values = nullptr);

// Camera-to-world 4x4 of a world-to-camera pose, camera axes turned to OpenGL's (nerfstudio,
// instant-ngp): columns 1 and 2 of the rotation negated.
Eigen::Matrix4d NerfTransformMatrix(const SE3& T_cw);

struct NerfFrame {
  std::string file_path;  // image, relative to transforms.json
  std::string mask_path;  // relative to transforms.json; empty = no mask
  SE3 T_cw;
  int keyframe_id = -1;
};

// transforms.json: camera_model OPENCV (fl_x, fl_y, cx, cy, w, h, k1, k2, p1, p2, k3), frames,
// ply_file_path (empty: omitted), and `extra` under the key "dynref".
nlohmann::json TransformsJson(const Camera& camera, const std::vector<NerfFrame>& frames,
                              const std::string& ply_file_path, const nlohmann::json& extra);

// Colour of a BGR image at a raw pixel, bilinear, as RGB in [0, 1]; false outside the image.
bool SampleRgb(const cv::Mat& bgr, double u, double v, Eigen::Vector3d* rgb);

}  // namespace dynref::epi
