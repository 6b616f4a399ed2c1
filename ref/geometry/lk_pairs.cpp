#include "geometry/lk_pairs.h"

#include "core/parallel.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/video/tracking.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace dynref::geometry {

void LkOptions::Check() const {
  if (window_px < 3 || window_px % 2 == 0) throw std::invalid_argument("window_px must be odd >= 3");
  if (max_level < 0) throw std::invalid_argument("max_level must be >= 0");
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be >= 1");
  if (!(epsilon > 0)) throw std::invalid_argument("epsilon must be > 0");
  if (border_px < 1) throw std::invalid_argument("border_px must be >= 1 (3x3 patch)");
  if (threads < 1) throw std::invalid_argument("threads must be >= 1");
  if (!(patch_sad_max >= 0)) throw std::invalid_argument("patch_sad_max must be >= 0");
}

std::vector<LkPair> TrackBackward(const cv::Mat& prev_grey, const cv::Mat& cur_grey,
                                  const std::vector<cv::Point2f>& points_cur,
                                  const LkOptions& options) {
  options.Check();
  if (prev_grey.type() != CV_8U || cur_grey.type() != CV_8U || prev_grey.size() != cur_grey.size())
    throw std::invalid_argument("TrackBackward: images must be CV_8U of equal size");
  std::vector<LkPair> pairs(points_cur.size());
  if (points_cur.empty()) return pairs;
  const size_t n = points_cur.size();
  std::vector<cv::Point2f> points_prev(n);
  std::vector<uchar> status(n);
  // Slices of at least 64 points (below that the second pyramid costs more than it saves).
  const int slices = std::max(1, std::min(options.threads, static_cast<int>(n / 64)));
  ParallelFor(slices, options.threads, [&](int s) {
    const size_t begin = n * static_cast<size_t>(s) / static_cast<size_t>(slices);
    const size_t end = n * static_cast<size_t>(s + 1) / static_cast<size_t>(slices);
    const std::vector<cv::Point2f> in(points_cur.begin() + static_cast<std::ptrdiff_t>(begin),
                                      points_cur.begin() + static_cast<std::ptrdiff_t>(end));
    std::vector<cv::Point2f> out;
    std::vector<uchar> st;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(
        cur_grey, prev_grey, in, out, st, err, cv::Size(options.window_px, options.window_px), options.max_level,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options.max_iterations, options.epsilon));
    std::copy(out.begin(), out.end(), points_prev.begin() + static_cast<std::ptrdiff_t>(begin));
    std::copy(st.begin(), st.end(), status.begin() + static_cast<std::ptrdiff_t>(begin));
  });
  for (size_t i = 0; i < points_cur.size(); ++i) {
    LkPair& p = pairs[i];
    p.p_cur = points_cur[i];
    p.p_prev = points_prev[i];
    const bool inside = std::isfinite(p.p_prev.x) && std::isfinite(p.p_prev.y) && p.p_prev.x >= 0 &&
                        p.p_prev.y >= 0 && p.p_prev.x <= prev_grey.cols - 1 &&
                        p.p_prev.y <= prev_grey.rows - 1;
    p.tracked = status[i] != 0 && inside;
    if (!p.tracked) p.prune_reason = "lk-failed";
  }
  return pairs;
}

double PatchSad3x3(const cv::Mat& prev_grey, const cv::Mat& cur_grey, cv::Point2f p_prev,
                   cv::Point2f p_cur) {
  const int x1 = static_cast<int>(p_prev.x), y1 = static_cast<int>(p_prev.y);
  const int x2 = static_cast<int>(p_cur.x), y2 = static_cast<int>(p_cur.y);
  double sum = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      sum += std::abs(static_cast<int>(prev_grey.at<uchar>(y1 + dy, x1 + dx)) -
                      static_cast<int>(cur_grey.at<uchar>(y2 + dy, x2 + dx)));
  return sum;
}

void PrunePair(const cv::Mat& prev_grey, const cv::Mat& cur_grey, bool in_mask,
               const LkOptions& options, LkPair& pair) {
  if (!pair.tracked) {
    pair.prune_reason = "lk-failed";
    return;
  }
  const int b = options.border_px;
  auto near_border = [&](cv::Point2f p) {
    const int x = static_cast<int>(p.x), y = static_cast<int>(p.y);
    return x < b || x >= cur_grey.cols - b || y < b || y >= cur_grey.rows - b;
  };
  if (near_border(pair.p_prev) || near_border(pair.p_cur)) {
    pair.prune_reason = "border";
    return;
  }
  pair.patch_sad = PatchSad3x3(prev_grey, cur_grey, pair.p_prev, pair.p_cur);
  if (pair.patch_sad > options.patch_sad_max) {
    pair.prune_reason = "patch-sad";
    return;
  }
  pair.prune_reason = in_mask ? "in-mask" : "";
}

void UndistortedPairPixels(const Camera& camera, const std::vector<LkPair>& pairs, std::vector<cv::Point2f>* prev,
                           std::vector<cv::Point2f>* cur) {
  prev->clear();
  cur->clear();
  for (const LkPair& p : pairs) prev->push_back(p.p_prev), cur->push_back(p.p_cur);
  if (!camera.HasDistortion() || pairs.empty()) return;
  const cv::Mat K(camera.K()), D = camera.DistCoeffs();
  cv::undistortPoints(std::vector<cv::Point2f>(*prev), *prev, K, D, cv::noArray(), K);
  cv::undistortPoints(std::vector<cv::Point2f>(*cur), *cur, K, D, cv::noArray(), K);
}

}  // namespace dynref::geometry
