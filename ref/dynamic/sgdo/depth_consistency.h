// seed 001, Sec. 3.4, Eq. (8)-(9): depth-consistency test of a feature of frame i against the
// depth map of keyframe k, and Sec. 3.5 static weight omega = exp(-lambda eps^2).
//   P_c = d_i(p) K^-1 [u, v, 1]^T;  X_k = T_kw T_iw^-1 P_c  (paper: T_k^-1 T_i, camera-to-world)
//   (u', v') = (fx x_k/z_k + cx, fy y_k/z_k + cy)   (reconstructed: the printed pi omits K, E5)
//   d_k = D_k(round(u'), round(v'))                  (nearest pixel, E5)
//   eps = (z_k - d_k) / d_k  (E8);  reject iff |eps| > eta
// Skipped (kept, omega = 1; spec proposal): no depth at p, z_k <= 0, (u', v') outside the image,
// d_k invalid (0 or not finite).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "core/intrinsics.h"
#include "io/camera.h"

namespace dynref::sgdo {

struct DepthConsistencyOptions {
  double eta = 0.1;      // not stated ("empirical value"): above Kinect noise, below motion
  double lambda = 100;   // not stated: 1/eta^2
  void Check() const;
};

struct DepthCheck {
  bool tested = false;
  std::string skip_reason;  // "" when tested: "no-depth" | "behind-kf" | "outside-kf" | "kf-no-depth"
  double u_k = 0, v_k = 0;  // projection into the keyframe
  double z_k = 0;           // depth of X_k in the keyframe camera
  double d_k = 0;           // keyframe depth map value
  double eps = 0;           // normalised depth residual (0 when skipped)
};

// T_kc = T_kw * T_cw^-1 (keyframe_from_current). depth_kf: CV_32F metres, 0 = invalid.
// (u, v) and (u_k, v_k) are undistorted pixels; the keyframe's depth image is raw (distorted),
// so d_k is read at the distorted position of (u_k, v_k) when `distortion` has distortion
// (issue 21 defect 4: TUM fr1/fr2). u_k, v_k in the result stay undistorted.
DepthCheck CheckDepthConsistency(double u, double v, double depth_i_m, const Intrinsics& K,
                                 const Eigen::Isometry3d& T_kc, const cv::Mat& depth_kf,
                                 const Camera* distortion = nullptr);

// Sec. 3.5: omega(p) = exp(-lambda * eps^2).
inline double StaticWeight(double eps, double lambda) { return std::exp(-lambda * eps * eps); }

}  // namespace dynref::sgdo
