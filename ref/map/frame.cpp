// Frame: ORB-SLAM2 Frame (RGB-D constructor) geometry and the per-feature method state.
#include "map/frame.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

#include "trace/trace_writer.h"

namespace dynref {
namespace {

// A depth discontinuity at (u, v): a pixel of the 5x5 window without depth, or whose depth differs
// from d by more than rel * d (window clipped at the image border).
bool OnDepthEdge(const cv::Mat& depth_m, int u, int v, float d, double rel) {
  const double tol = rel * d;
  for (int y = std::max(0, v - 2); y <= std::min(depth_m.rows - 1, v + 2); ++y)
    for (int x = std::max(0, u - 2); x <= std::min(depth_m.cols - 1, u + 2); ++x) {
      const float e = depth_m.at<float>(y, x);
      if (!(e > 0) || !std::isfinite(e) || std::fabs(double(e) - double(d)) > tol) return true;
    }
  return false;
}

}  // namespace

ScalePyramid ScalePyramid::Make(int n_levels, double scale_factor) {
  ScalePyramid p;
  p.n_levels = n_levels;
  p.scale_factor = scale_factor;
  p.scale.resize(n_levels);
  p.inv_scale.resize(n_levels);
  p.sigma2.resize(n_levels);
  p.inv_sigma2.resize(n_levels);
  p.scale[0] = 1.0f;
  p.sigma2[0] = 1.0f;
  for (int i = 1; i < n_levels; ++i) {
    p.scale[i] = static_cast<float>(p.scale[i - 1] * scale_factor);
    p.sigma2[i] = p.scale[i] * p.scale[i];
  }
  for (int i = 0; i < n_levels; ++i) {
    p.inv_scale[i] = 1.0f / p.scale[i];
    p.inv_sigma2[i] = 1.0f / p.sigma2[i];
  }
  return p;
}

void Frame::Exclude(int i, const std::string& stage, const std::string& reason) {
  if (excluded_.empty()) excluded_.assign(N(), 0);
  if (excluded_[i]) return;
  excluded_[i] = 1;
  DropAssociation(i);
  if (trace != nullptr)
    trace->Decision(stage, trace::EntityKind::kFeature, FeatureId(i), false, reason);
}

void Frame::DropAssociation(int i) {
  if (i >= static_cast<int>(map_point_ids.size()) || map_point_ids[i] < 0) return;
  if (dropped_map_point_ids_.size() < map_point_ids.size()) dropped_map_point_ids_.resize(map_point_ids.size(), -1);
  dropped_map_point_ids_[i] = map_point_ids[i];
  map_point_ids[i] = -1;
}

int64_t Frame::AssociatedMapPoint(int i) const {
  if (i < static_cast<int>(map_point_ids.size()) && map_point_ids[i] >= 0) return map_point_ids[i];
  return i < static_cast<int>(dropped_map_point_ids_.size()) ? dropped_map_point_ids_[i] : -1;
}

void Frame::SetWeight(int i, double w) {
  if (weights_.empty()) weights_.assign(N(), 1.0);
  weights_[i] = w;
}

int Frame::ExcludedCount() const {
  int n = 0;
  for (uint8_t e : excluded_) n += e;
  return n;
}

std::string Frame::FeatureId(int i) const {
  return "f" + std::to_string(index) + "." + std::to_string(i);
}

void Frame::FinishFeatures(const Camera& cam, double depth_edge_rel) {
  camera = &cam;
  const size_t n = keys.size();
  // Undistortion (ORB-SLAM2 Frame::UndistortKeyPoints, Frame::ComputeImageBounds).
  keys_un = keys;
  if (cam.HasDistortion() && n > 0) {
    cv::Mat pts(static_cast<int>(n), 1, CV_32FC2);
    for (size_t i = 0; i < n; ++i) pts.at<cv::Vec2f>(static_cast<int>(i)) = {keys[i].pt.x, keys[i].pt.y};
    cv::Mat K(cam.K()), out;
    cv::undistortPoints(pts, out, K, cam.DistCoeffs(), cv::noArray(), K);
    for (size_t i = 0; i < n; ++i) {
      const cv::Vec2f p = out.at<cv::Vec2f>(static_cast<int>(i));
      keys_un[i].pt = {p[0], p[1]};
    }
  }
  if (cam.HasDistortion()) {
    cv::Mat corners = (cv::Mat_<cv::Vec2f>(4, 1) << cv::Vec2f(0, 0),
                       cv::Vec2f(static_cast<float>(cam.width), 0),
                       cv::Vec2f(0, static_cast<float>(cam.height)),
                       cv::Vec2f(static_cast<float>(cam.width), static_cast<float>(cam.height)));
    cv::Mat K(cam.K()), out;
    cv::undistortPoints(corners, out, K, cam.DistCoeffs(), cv::noArray(), K);
    const auto c = [&](int i) { return out.at<cv::Vec2f>(i); };
    min_x = std::min(c(0)[0], c(2)[0]);
    max_x = std::max(c(1)[0], c(3)[0]);
    min_y = std::min(c(0)[1], c(1)[1]);
    max_y = std::max(c(2)[1], c(3)[1]);
  } else {
    min_x = 0;
    max_x = static_cast<float>(cam.width);
    min_y = 0;
    max_y = static_cast<float>(cam.height);
  }
  // Depth at the raw keypoint, virtual right coordinate (ORB-SLAM2 ComputeStereoFromRGBD).
  depth.assign(n, -1.0f);
  u_right.assign(n, -1.0f);
  for (size_t i = 0; i < n; ++i) {
    const int v = static_cast<int>(keys[i].pt.y), u = static_cast<int>(keys[i].pt.x);
    if (depth_m.empty() || v < 0 || u < 0 || v >= depth_m.rows || u >= depth_m.cols) continue;
    const float d = depth_m.at<float>(v, u);
    if (d > 0 && std::isfinite(d) && depth_edge_rel > 0 && OnDepthEdge(depth_m, u, v, d, depth_edge_rel)) continue;
    if (d > 0 && std::isfinite(d)) {
      depth[i] = d;
      u_right[i] = keys_un[i].pt.x - static_cast<float>(cam.bf) / d;
    }
  }
  map_point_ids.assign(n, -1);
  outlier.assign(n, 0);
  excluded_.clear();
  weights_.clear();
  dropped_map_point_ids_.clear();
  // Grid (ORB-SLAM2 AssignFeaturesToGrid / PosInGrid).
  grid_.assign(kGridCols * kGridRows, {});
  grid_inv_w_ = kGridCols / (max_x - min_x);
  grid_inv_h_ = kGridRows / (max_y - min_y);
  for (size_t i = 0; i < n; ++i) {
    const int gx = static_cast<int>(std::round((keys_un[i].pt.x - min_x) * grid_inv_w_));
    const int gy = static_cast<int>(std::round((keys_un[i].pt.y - min_y) * grid_inv_h_));
    if (gx < 0 || gx >= kGridCols || gy < 0 || gy >= kGridRows) continue;
    grid_[gx * kGridRows + gy].push_back(static_cast<int>(i));
  }
}

Eigen::Vector3d Frame::UnprojectWorld(int i) const {
  const double z = depth[i];
  const double u = keys_un[i].pt.x, v = keys_un[i].pt.y;
  const Eigen::Vector3d X_c((u - camera->cx) * z / camera->fx, (v - camera->cy) * z / camera->fy, z);
  return T_cw.inverse() * X_c;
}

bool Frame::IsClose(int i) const {
  return depth[i] > 0 && depth[i] < camera->th_depth * camera->baseline_m();
}

std::vector<int> Frame::FeaturesInArea(float x, float y, float r, int min_level, int max_level) const {
  std::vector<int> out;
  if (grid_.empty()) return out;
  const int min_cx = std::max(0, static_cast<int>(std::floor((x - min_x - r) * grid_inv_w_)));
  if (min_cx >= kGridCols) return out;
  const int max_cx = std::min(kGridCols - 1, static_cast<int>(std::ceil((x - min_x + r) * grid_inv_w_)));
  if (max_cx < 0) return out;
  const int min_cy = std::max(0, static_cast<int>(std::floor((y - min_y - r) * grid_inv_h_)));
  if (min_cy >= kGridRows) return out;
  const int max_cy = std::min(kGridRows - 1, static_cast<int>(std::ceil((y - min_y + r) * grid_inv_h_)));
  if (max_cy < 0) return out;
  const bool check_levels = (min_level > 0) || (max_level >= 0);
  for (int ix = min_cx; ix <= max_cx; ++ix) {
    for (int iy = min_cy; iy <= max_cy; ++iy) {
      for (int j : grid_[ix * kGridRows + iy]) {
        if (IsExcluded(j)) continue;
        const cv::KeyPoint& kp = keys_un[j];
        if (check_levels) {
          if (kp.octave < min_level) continue;
          if (max_level >= 0 && kp.octave > max_level) continue;
        }
        if (std::fabs(kp.pt.x - x) < r && std::fabs(kp.pt.y - y) < r) out.push_back(j);
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace dynref
