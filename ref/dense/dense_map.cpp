#include "dense/dense_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace dynref::dense {

void DenseMapOptions::Check() const {
  if (!(keyframe_leaf_m > 0)) throw std::invalid_argument("keyframe_leaf_m must be > 0");
  if (!(global_leaf_m > 0)) throw std::invalid_argument("global_leaf_m must be > 0");
  if (filter_every_keyframes < 1) throw std::invalid_argument("filter_every_keyframes must be >= 1");
  if (!(min_depth_m >= 0 && max_depth_m > min_depth_m))
    throw std::invalid_argument("min_depth_m/max_depth_m must satisfy 0 <= min < max");
  if (pixel_stride < 1) throw std::invalid_argument("pixel_stride must be >= 1");
  if (!(context_margin_m > 0)) throw std::invalid_argument("context_margin_m must be > 0");
  sor.Check();
}

bool ClassColour(int class_id, uint8_t& r, uint8_t& g, uint8_t& b) {
  if (class_id < 0) return false;
  if (class_id == 62) {  // tv (monitor): green, Fig. 8c
    r = 0, g = 255, b = 0;
    return true;
  }
  if (class_id == 56) {  // chair: red, Fig. 8c
    r = 255, g = 0, b = 0;
    return true;
  }
  // Fixed palette: hue from the class id (golden-ratio steps), full saturation.
  const double h = std::fmod(class_id * 0.61803398874989485, 1.0) * 6.0;
  const int i = static_cast<int>(h);
  const double f = h - i;
  const uint8_t q = static_cast<uint8_t>(std::lround(255 * (1 - f)));
  const uint8_t t = static_cast<uint8_t>(std::lround(255 * f));
  switch (i % 6) {
    case 0: r = 255, g = t, b = 0; break;
    case 1: r = q, g = 255, b = 0; break;
    case 2: r = 0, g = 255, b = t; break;
    case 3: r = 0, g = q, b = 255; break;
    case 4: r = t, g = 0, b = 255; break;
    default: r = 255, g = 0, b = q; break;
  }
  return true;
}

cv::Mat UndistortedRays(const Camera& camera) {
  if (!camera.HasDistortion()) return cv::Mat();
  std::vector<cv::Point2d> px, und;
  px.reserve(static_cast<size_t>(camera.width) * camera.height);
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) px.emplace_back(u, v);
  // Normalised (x, y); 100 fixed-point iterations (OpenCV's default 5 leaves ~0.1 px at the
  // corners of a TUM fr1 image).
  cv::undistortPoints(px, und, cv::Mat(camera.K()), camera.DistCoeffs(), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  cv::Mat rays(camera.height, camera.width, CV_64FC2);
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const cv::Point2d& q = und[static_cast<size_t>(v) * camera.width + u];
      rays.at<cv::Vec2d>(v, u) = cv::Vec2d(q.x, q.y);
    }
  return rays;
}

PointCloud BackProjectKeyframe(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& exclude,
                               const cv::Mat& class_labels, const Camera& camera,
                               const DenseMapOptions& options, const cv::Mat& rays) {
  options.Check();
  if (!rays.empty() && (rays.type() != CV_64FC2 || rays.size() != depth_m.size()))
    throw std::invalid_argument("BackProjectKeyframe: rays must be CV_64FC2 of image size");
  if (bgr.type() != CV_8UC3 || depth_m.type() != CV_32F || bgr.size() != depth_m.size())
    throw std::invalid_argument("BackProjectKeyframe: need CV_8UC3 colour and CV_32F depth of equal size");
  if (!exclude.empty() && (exclude.type() != CV_8U || exclude.size() != depth_m.size()))
    throw std::invalid_argument("BackProjectKeyframe: exclude mask must be CV_8U of image size");
  if (!class_labels.empty() && (class_labels.type() != CV_16S || class_labels.size() != depth_m.size()))
    throw std::invalid_argument("BackProjectKeyframe: class labels must be CV_16S of image size");
  PointCloud out;
  const int s = options.pixel_stride;
  for (int v = 0; v < depth_m.rows; v += s) {
    for (int u = 0; u < depth_m.cols; u += s) {
      const float z = depth_m.at<float>(v, u);
      if (!(z >= options.min_depth_m && z <= options.max_depth_m)) continue;
      if (!exclude.empty() && exclude.at<uint8_t>(v, u) != 0) continue;
      ColoredPoint p;
      if (rays.empty()) {
        p.x = static_cast<float>((u - camera.cx) * z / camera.fx);
        p.y = static_cast<float>((v - camera.cy) * z / camera.fy);
      } else {
        const cv::Vec2d r = rays.at<cv::Vec2d>(v, u);
        p.x = static_cast<float>(r[0] * z);
        p.y = static_cast<float>(r[1] * z);
      }
      p.z = z;
      const cv::Vec3b c = bgr.at<cv::Vec3b>(v, u);
      p.b = c[0], p.g = c[1], p.r = c[2];
      if (!class_labels.empty()) p.class_id = class_labels.at<int16_t>(v, u);
      if (options.colour_by_class) ClassColour(p.class_id, p.r, p.g, p.b);
      out.push_back(p);
    }
  }
  return out;
}

DenseMap::DenseMap(const DenseMapOptions& options) : options_(options), grid_(options.global_leaf_m) {
  options_.Check();
}

KeyframeInsertStats DenseMap::AddKeyframe(const cv::Mat& bgr, const cv::Mat& depth_m,
                                          const cv::Mat& exclude, const cv::Mat& class_labels,
                                          const Camera& camera, const SE3& T_wc) {
  KeyframeInsertStats st;
  if (!rays_ready_) rays_ = UndistortedRays(camera), rays_ready_ = true;  // the camera of a run is fixed
  const PointCloud local = BackProjectKeyframe(bgr, depth_m, exclude, class_labels, camera, options_, rays_);
  st.back_projected = static_cast<int64_t>(local.size());
  // Single-frame voxel downsampling in the camera frame, then transform to world.
  const PointCloud voxel = VoxelDownsample(local, options_.keyframe_leaf_m);
  st.after_voxel = static_cast<int64_t>(voxel.size());
  const Eigen::Matrix3d R = T_wc.linear();
  const Eigen::Vector3d t = T_wc.translation();
  for (ColoredPoint p : voxel) {
    const Eigen::Vector3d w = R * Eigen::Vector3d(p.x, p.y, p.z) + t;
    p.x = static_cast<float>(w.x()), p.y = static_cast<float>(w.y()), p.z = static_cast<float>(w.z());
    (options_.incremental ? pending_ : cloud_).push_back(p);
  }
  ++keyframes_;
  if (++since_filter_ >= options_.filter_every_keyframes) {
    st.sor_removed = options_.incremental ? FilterPending() : FilterGlobal();
    st.global_filter_ran = true;
  }
  st.map_points = static_cast<int64_t>(options_.incremental ? grid_.size() + pending_.size() : cloud_.size());
  return st;
}

int64_t DenseMap::FilterPending() {
  since_filter_ = 0;
  if (pending_.empty()) return 0;
  // The new points (one surface seen by several keyframes) are first merged into voxels of the
  // global leaf; SOR judges these voxels, with the map's voxels around them (their bounding box
  // grown by the margin) as neighbours; the raw points of the kept voxels then enter the global
  // grid, so its centroids are exactly those of every accepted point.
  VoxelGrid batch(options_.global_leaf_m);
  batch.Add(pending_);
  const PointCloud centroids = batch.Cloud();
  std::array<float, 3> lo{centroids[0].x, centroids[0].y, centroids[0].z}, hi = lo;
  for (const ColoredPoint& p : centroids) {
    lo = {std::min(lo[0], p.x), std::min(lo[1], p.y), std::min(lo[2], p.z)};
    hi = {std::max(hi[0], p.x), std::max(hi[1], p.y), std::max(hi[2], p.z)};
  }
  const float m = static_cast<float>(options_.context_margin_m);
  for (int a = 0; a < 3; ++a) lo[size_t(a)] -= m, hi[size_t(a)] += m;
  const std::vector<uint8_t> keep = StatisticalOutlierMask(centroids, grid_.CentroidsIn(lo, hi), options_.sor);
  const std::vector<VoxelGrid::Key> keys = batch.Keys();
  std::map<VoxelGrid::Key, bool> kept_voxel;
  for (size_t i = 0; i < keys.size(); ++i) kept_voxel.emplace(keys[i], keep[i] != 0);
  PointCloud kept;
  kept.reserve(pending_.size());
  int64_t removed = 0;
  for (const ColoredPoint& p : pending_) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    if (kept_voxel.at(batch.KeyOf(p))) kept.push_back(p);
    else ++removed;
  }
  grid_.Add(kept);
  pending_.clear();
  return removed;
}

int64_t DenseMap::FilterGlobal() {
  since_filter_ = 0;
  const size_t before = cloud_.size();
  PointCloud kept = StatisticalOutlierRemoval(cloud_, options_.sor);
  const int64_t removed = static_cast<int64_t>(before - kept.size());
  cloud_ = VoxelDownsample(kept, options_.global_leaf_m);
  return removed;
}

int64_t DenseMap::Finish() {
  if (options_.incremental) {
    int64_t removed = 0;
    if (options_.final_filter && since_filter_ > 0) removed = FilterPending();
    grid_.Add(pending_);  // final_filter off: the last points enter unfiltered
    pending_.clear();
    cloud_ = grid_.Cloud();
    return removed;
  }
  if (!options_.final_filter || since_filter_ == 0) return 0;
  return FilterGlobal();
}

}  // namespace dynref::dense
