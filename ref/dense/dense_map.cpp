#include "dense/dense_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

#include "core/parallel.h"

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
                               const DenseMapOptions& options, const cv::Mat& rays, int threads) {
  options.Check();
  if (!rays.empty() && (rays.type() != CV_64FC2 || rays.size() != depth_m.size()))
    throw std::invalid_argument("BackProjectKeyframe: rays must be CV_64FC2 of image size");
  if (bgr.type() != CV_8UC3 || depth_m.type() != CV_32F || bgr.size() != depth_m.size())
    throw std::invalid_argument("BackProjectKeyframe: need CV_8UC3 colour and CV_32F depth of equal size");
  if (!exclude.empty() && (exclude.type() != CV_8U || exclude.size() != depth_m.size()))
    throw std::invalid_argument("BackProjectKeyframe: exclude mask must be CV_8U of image size");
  if (!class_labels.empty() && (class_labels.type() != CV_16S || class_labels.size() != depth_m.size()))
    throw std::invalid_argument("BackProjectKeyframe: class labels must be CV_16S of image size");
  const int s = options.pixel_stride;
  const int sampled_rows = (depth_m.rows + s - 1) / s;
  // Bands of kBand sampled rows, one task each (one band for one thread: no concatenation).
  const int kBand = threads <= 1 ? std::max(1, sampled_rows) : 16;
  std::vector<PointCloud> bands(static_cast<size_t>((sampled_rows + kBand - 1) / kBand));
  ParallelFor(static_cast<int>(bands.size()), threads, [&](int band) {
    PointCloud& out = bands[static_cast<size_t>(band)];
    const int v_end = std::min(depth_m.rows, (band + 1) * kBand * s);
    for (int v = band * kBand * s; v < v_end; v += s) {
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
  });
  if (bands.size() == 1) return std::move(bands[0]);
  size_t n = 0;
  for (const PointCloud& b : bands) n += b.size();
  PointCloud out;
  out.reserve(n);
  for (const PointCloud& b : bands) out.insert(out.end(), b.begin(), b.end());
  return out;
}

DenseMap::DenseMap(const DenseMapOptions& options)
    : options_(options), grid_(options.global_leaf_m),
      bricks_(options.global_leaf_m, options.context_margin_m) {
  options_.Check();
}

KeyframeInsertStats DenseMap::AddKeyframe(const cv::Mat& bgr, const cv::Mat& depth_m,
                                          const cv::Mat& exclude, const cv::Mat& class_labels,
                                          const Camera& camera, const SE3& T_wc) {
  KeyframeInsertStats st;
  if (!rays_ready_) rays_ = UndistortedRays(camera), rays_ready_ = true;  // the camera of a run is fixed
  const PointCloud local = BackProjectKeyframe(bgr, depth_m, exclude, class_labels, camera, options_, rays_, threads_);
  st.back_projected = static_cast<int64_t>(local.size());
  // Single-frame voxel downsampling in the camera frame, then transform to world.
  const PointCloud voxel = VoxelDownsample(local, options_.keyframe_leaf_m);
  st.after_voxel = static_cast<int64_t>(voxel.size());
  const Eigen::Matrix3d R = T_wc.linear();
  const Eigen::Vector3d t = T_wc.translation();
  PointCloud& out = options_.incremental ? pending_ : cloud_;
  out.reserve(out.size() + voxel.size());
  for (ColoredPoint p : voxel) {
    const Eigen::Vector3d w = R * Eigen::Vector3d(p.x, p.y, p.z) + t;
    p.x = static_cast<float>(w.x()), p.y = static_cast<float>(w.y()), p.z = static_cast<float>(w.z());
    out.push_back(p);
  }
  ++keyframes_;
  ++since_filter_;
  // Incremental mode seeds the map with the first keyframe (one keyframe's SOR instead of N's
  // from scratch); afterwards both modes filter every N keyframes.
  if (since_filter_ >= options_.filter_every_keyframes || (options_.incremental && grid_.size() == 0)) {
    st.sor_removed = options_.incremental ? FilterBatch() : FilterGlobal();
    st.global_filter_ran = true;
  }
  st.map_points = static_cast<int64_t>(options_.incremental ? grid_.size() + pending_.size() : cloud_.size());
  return st;
}

bool DenseMap::TouchesMap(const VoxelKey& v) const {
  for (int64_t dx = -1; dx <= 1; ++dx)
    for (int64_t dy = -1; dy <= 1; ++dy)
      for (int64_t dz = -1; dz <= 1; ++dz)
        if ((dx | dy | dz) != 0 && grid_.Find({v[0] + dx, v[1] + dy, v[2] + dz}) != VoxelKeyIndex::kNone) return true;
  return false;
}

void DenseMap::MergeIntoMap(const VoxelKey& key, const VoxelAccumulator& points) {
  const size_t before = grid_.size();
  const uint32_t i = grid_.Merge(key, points);
  if (i == before) bricks_.Add(key, grid_.PositionAt(i));
  else bricks_.Move(i, grid_.PositionAt(i));
}

int64_t DenseMap::FilterBatch() {
  since_filter_ = 0;
  if (pending_.empty()) return 0;
  // The new points (one surface seen by several keyframes) are merged into voxels of the global
  // leaf. A voxel the map already holds, or one touching a map voxel (its 26-neighbourhood: the
  // known surface seen again through depth noise), joins the map; every other voxel is judged by
  // SOR against the map so grown and the other judged voxels: its mean distance to its k nearest
  // neighbours, each capped at context_margin_m (exact within it: VoxelBricks), against the
  // threshold from the distribution over the map's voxels (their statistic when they were judged
  // and kept) and the judged ones -- the cloud SOR over the whole map would see. The first filter
  // (empty map) is plain SOR of the batch with capped distances. Accepted voxels' sums enter the
  // global grid, so its centroids are those of every accepted point. A rejected voxel leaves no
  // trace and is judged afresh when observed again.
  const SortedVoxels batch = SortIntoVoxels(pending_, options_.global_leaf_m);
  pending_.clear();
  // Decided against the map as it was before this batch, then merged.
  std::vector<uint32_t> joining, judged;
  for (uint32_t v = 0; v < batch.size(); ++v)
    (grid_.Find(batch.keys[v]) != VoxelKeyIndex::kNone || TouchesMap(batch.keys[v]) ? joining : judged).push_back(v);
  for (uint32_t v : joining) MergeIntoMap(batch.keys[v], batch.acc[v]);
  int64_t removed = 0;
  if (judged.empty()) return 0;
  const std::vector<double> mean_dist = JudgedStatistic(batch, judged);
  std::vector<uint8_t> keep(judged.size(), 1);
  if (!mean_dist.empty()) {
    SorStatistics cloud = accepted_stats_;  // the cloud SOR would see: the map plus the judged voxels
    cloud.Add(mean_dist);
    const double threshold = cloud.Threshold(options_.sor.std_mult);
    std::vector<double> accepted;
    for (size_t j = 0; j < judged.size(); ++j) {
      keep[j] = mean_dist[j] <= threshold ? 1 : 0;
      if (keep[j]) accepted.push_back(mean_dist[j]);
    }
    accepted_stats_.Add(accepted);
  }
  for (size_t j = 0; j < judged.size(); ++j) {
    if (keep[j]) MergeIntoMap(batch.keys[judged[j]], batch.acc[judged[j]]);
    else removed += batch.acc[judged[j]].n;
  }
  return removed;
}

std::vector<double> DenseMap::JudgedStatistic(const SortedVoxels& batch, const std::vector<uint32_t>& judged) const {
  const int k = options_.sor.k;
  if (grid_.size() + judged.size() <= static_cast<size_t>(k)) return {};  // as MeanKnnDistances
  VoxelBricks judged_bricks(options_.global_leaf_m, options_.context_margin_m);
  for (uint32_t v : judged) judged_bricks.Add(batch.keys[v], batch.acc[v].Position());
  return CappedMeanKnnDistances(judged_bricks, {&bricks_}, k, options_.context_margin_m, threads_);
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
    if (options_.final_filter && since_filter_ > 0) removed = FilterBatch();
    const SortedVoxels rest = SortIntoVoxels(pending_, options_.global_leaf_m);  // final_filter off: unfiltered
    for (size_t v = 0; v < rest.size(); ++v) MergeIntoMap(rest.keys[v], rest.acc[v]);
    pending_ = PointCloud();
    bricks_ = VoxelBricks(options_.global_leaf_m, options_.context_margin_m);  // no filter after Finish
    cloud_ = grid_.Cloud();
    return removed;
  }
  if (!options_.final_filter || since_filter_ == 0) return 0;
  return FilterGlobal();
}

}  // namespace dynref::dense
