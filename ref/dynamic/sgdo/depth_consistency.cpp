#include "dynamic/sgdo/depth_consistency.h"

#include <cmath>
#include <stdexcept>

namespace dynref::sgdo {

void DepthConsistencyOptions::Check() const {
  if (!(eta > 0)) throw std::invalid_argument("eta must be > 0");
  if (!(lambda >= 0)) throw std::invalid_argument("lambda must be >= 0");
}

DepthCheck CheckDepthConsistency(double u, double v, double depth_i_m, const Intrinsics& K,
                                 const Eigen::Isometry3d& T_kc, const cv::Mat& depth_kf, const Camera* distortion) {
  DepthCheck r;
  if (!(depth_i_m > 0) || !std::isfinite(depth_i_m)) {
    r.skip_reason = "no-depth";
    return r;
  }
  // Eq. (8)-(9): inverse projection with the keypoint's depth.
  const Eigen::Vector3d P_c(depth_i_m * (u - K.cx) / K.fx, depth_i_m * (v - K.cy) / K.fy, depth_i_m);
  const Eigen::Vector3d X_k = T_kc * P_c;
  r.z_k = X_k.z();
  if (!(X_k.z() > 0)) {
    r.skip_reason = "behind-kf";
    return r;
  }
  r.u_k = K.fx * X_k.x() / X_k.z() + K.cx;
  r.v_k = K.fy * X_k.y() / X_k.z() + K.cy;
  const cv::Point2d raw = distortion != nullptr ? distortion->Distort(r.u_k, r.v_k) : cv::Point2d(r.u_k, r.v_k);
  const long x = std::lround(raw.x), y = std::lround(raw.y);
  if (depth_kf.empty() || x < 0 || y < 0 || x >= depth_kf.cols || y >= depth_kf.rows) {
    r.skip_reason = "outside-kf";
    return r;
  }
  r.d_k = depth_kf.at<float>(static_cast<int>(y), static_cast<int>(x));
  if (!(r.d_k > 0) || !std::isfinite(r.d_k)) {
    r.skip_reason = "kf-no-depth";
    return r;
  }
  r.eps = (r.z_k - r.d_k) / r.d_k;
  r.tested = true;
  return r;
}

}  // namespace dynref::sgdo
