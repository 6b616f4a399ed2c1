// The one pinhole-intrinsics type of dynref (issue 12): fx, fy, cx, cy in pixels, the image size
// and ORB-SLAM2's bf (virtual stereo baseline * fx, px*m; 0 where unused). Scalar is double
// everywhere except the synthetic renderer, which rasterises in float (PinholeIntrinsics<float>)
// so that generated sequences stay bit-identical. Distortion lives in io/Camera, not here:
// these intrinsics act on undistorted coordinates.
#pragma once
#include <Eigen/Core>

namespace dynref {

template <typename Scalar>
struct PinholeIntrinsics {
  Scalar fx = 0, fy = 0, cx = 0, cy = 0;
  Scalar bf = 0;
  int width = 0, height = 0;

  // Pixel of a camera-frame point (z > 0 is the caller's business).
  Eigen::Matrix<Scalar, 2, 1> Project(const Eigen::Matrix<Scalar, 3, 1>& X_c) const {
    return {fx * X_c.x() / X_c.z() + cx, fy * X_c.y() / X_c.z() + cy};
  }
  // Camera-frame point at depth z (metres along the optical axis) behind pixel (u, v).
  Eigen::Matrix<Scalar, 3, 1> Backproject(Scalar u, Scalar v, Scalar z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
  bool Contains(Scalar u, Scalar v) const { return u >= 0 && v >= 0 && u < width && v < height; }
};

using Intrinsics = PinholeIntrinsics<double>;

}  // namespace dynref
