// ORB-SLAM2 ORBextractor equivalent; see orb_extractor.h. Constants and control flow follow
// ORB-SLAM2 src/ORBextractor.cc (PATCH_SIZE 31, EDGE_THRESHOLD 19, W = 30 px cells).
#include "features/orb_extractor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <list>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "features/orb_pattern.h"

namespace dynref::features {
namespace {

constexpr int kPatchSize = 31;
constexpr int kHalfPatch = 15;
constexpr int kEdgeThreshold = 19;

// Intensity centroid angle in degrees (ORB-SLAM2 IC_Angle).
float IcAngle(const cv::Mat& image, cv::Point2f pt, const std::vector<int>& u_max) {
  int m_01 = 0, m_10 = 0;
  const uchar* center = &image.at<uchar>(cvRound(pt.y), cvRound(pt.x));
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m_10 += u * center[u];
  const int step = static_cast<int>(image.step1());
  for (int v = 1; v <= kHalfPatch; ++v) {
    int v_sum = 0;
    const int d = u_max[v];
    for (int u = -d; u <= d; ++u) {
      const int val_plus = center[u + v * step], val_minus = center[u - v * step];
      v_sum += (val_plus - val_minus);
      m_10 += u * (val_plus + val_minus);
    }
    m_01 += v * v_sum;
  }
  return cv::fastAtan2(static_cast<float>(m_01), static_cast<float>(m_10));
}

// rBRIEF descriptor of one keypoint (ORB-SLAM2 computeOrbDescriptor).
void OrbDescriptor(const cv::KeyPoint& kpt, const cv::Mat& img, uchar* desc) {
  const float factor_pi = static_cast<float>(CV_PI / 180.f);
  const float angle = kpt.angle * factor_pi;
  const float a = std::cos(angle), b = std::sin(angle);
  const uchar* center = &img.at<uchar>(cvRound(kpt.pt.y), cvRound(kpt.pt.x));
  const int step = static_cast<int>(img.step);
  const int* pattern = kOrbBitPattern31;
  auto value = [&](int idx) {
    const float px = static_cast<float>(pattern[2 * idx]);
    const float py = static_cast<float>(pattern[2 * idx + 1]);
    return center[cvRound(px * b + py * a) * step + cvRound(px * a - py * b)];
  };
  for (int i = 0; i < 32; ++i, pattern += 32) {
    int val = 0;
    for (int bit = 0; bit < 8; ++bit) {
      const int t0 = value(2 * bit), t1 = value(2 * bit + 1);
      val |= (t0 < t1) << bit;
    }
    desc[i] = static_cast<uchar>(val);
  }
}

struct Node {
  std::vector<cv::KeyPoint> keys;
  cv::Point2i ul, ur, bl, br;
  bool no_more = false;
  int64_t order = 0;  // creation order: deterministic tie-break (ORB-SLAM2 used the pointer)
  std::list<Node>::iterator it;

  void Divide(Node& n1, Node& n2, Node& n3, Node& n4) const {
    const int half_x = static_cast<int>(std::ceil(static_cast<float>(ur.x - ul.x) / 2));
    const int half_y = static_cast<int>(std::ceil(static_cast<float>(br.y - ul.y) / 2));
    n1.ul = ul; n1.ur = {ul.x + half_x, ul.y}; n1.bl = {ul.x, ul.y + half_y}; n1.br = {ul.x + half_x, ul.y + half_y};
    n2.ul = n1.ur; n2.ur = ur; n2.bl = n1.br; n2.br = {ur.x, ul.y + half_y};
    n3.ul = n1.bl; n3.ur = n1.br; n3.bl = bl; n3.br = {n1.br.x, bl.y};
    n4.ul = n3.ur; n4.ur = n2.br; n4.bl = n3.br; n4.br = br;
    for (Node* n : {&n1, &n2, &n3, &n4}) n->keys.reserve(keys.size());
    for (const cv::KeyPoint& kp : keys) {
      if (kp.pt.x < n1.ur.x) {
        (kp.pt.y < n1.br.y ? n1 : n3).keys.push_back(kp);
      } else {
        (kp.pt.y < n1.br.y ? n2 : n4).keys.push_back(kp);
      }
    }
    for (Node* n : {&n1, &n2, &n3, &n4}) n->no_more = n->keys.size() == 1;
  }
};

}  // namespace

void OrbOptions::Check() const {
  if (n_features < 1) throw InputError("orb options", "n_features must be >= 1");
  if (!(scale_factor > 1.0)) throw InputError("orb options", "scale_factor must be > 1");
  if (n_levels < 1 || n_levels > 16) throw InputError("orb options", "n_levels must be in 1..16");
  if (ini_th_fast < 1 || min_th_fast < 1 || min_th_fast > ini_th_fast)
    throw InputError("orb options", "need 1 <= min_th_fast <= ini_th_fast");
}

OrbExtractor::OrbExtractor(const OrbOptions& options) : options_(options) {
  options_.Check();
  const int L = options_.n_levels;
  scale_.resize(L);
  inv_scale_.resize(L);
  scale_[0] = 1.0f;
  for (int i = 1; i < L; ++i) scale_[i] = static_cast<float>(scale_[i - 1] * options_.scale_factor);
  for (int i = 0; i < L; ++i) inv_scale_[i] = 1.0f / scale_[i];
  pyramid_.resize(L);
  pyramid_border_.resize(L);

  // Features per level in geometric proportion (ORBextractor constructor).
  features_per_level_.resize(L);
  const float factor = 1.0f / static_cast<float>(options_.scale_factor);
  float n_desired = options_.n_features * (1 - factor) /
                    (1 - static_cast<float>(std::pow(static_cast<double>(factor), L)));
  int sum = 0;
  for (int level = 0; level < L - 1; ++level) {
    features_per_level_[level] = cvRound(n_desired);
    sum += features_per_level_[level];
    n_desired *= factor;
  }
  features_per_level_[L - 1] = std::max(options_.n_features - sum, 0);

  // Circular patch row extents (umax), symmetric by construction.
  umax_.resize(kHalfPatch + 1);
  const int vmax = cvFloor(kHalfPatch * std::sqrt(2.f) / 2 + 1);
  const int vmin = cvCeil(kHalfPatch * std::sqrt(2.f) / 2);
  const double hp2 = kHalfPatch * kHalfPatch;
  int v = 0, v0 = 0;
  for (v = 0; v <= vmax; ++v) umax_[v] = cvRound(std::sqrt(hp2 - v * v));
  for (v = kHalfPatch, v0 = 0; v >= vmin; --v) {
    while (umax_[v0] == umax_[v0 + 1]) ++v0;
    umax_[v] = v0;
    ++v0;
  }
}

void OrbExtractor::ComputePyramid(const cv::Mat& grey) {
  for (int level = 0; level < options_.n_levels; ++level) {
    const float scale = inv_scale_[level];
    const cv::Size sz(cvRound(grey.cols * scale), cvRound(grey.rows * scale));
    const cv::Size whole(sz.width + kEdgeThreshold * 2, sz.height + kEdgeThreshold * 2);
    cv::Mat temp(whole, grey.type());
    pyramid_[level] = temp(cv::Rect(kEdgeThreshold, kEdgeThreshold, sz.width, sz.height));
    if (level != 0) {
      cv::resize(pyramid_[level - 1], pyramid_[level], sz, 0, 0, cv::INTER_LINEAR);
      cv::copyMakeBorder(pyramid_[level], temp, kEdgeThreshold, kEdgeThreshold, kEdgeThreshold,
                         kEdgeThreshold, cv::BORDER_REFLECT_101 + cv::BORDER_ISOLATED);
    } else {
      cv::copyMakeBorder(grey, temp, kEdgeThreshold, kEdgeThreshold, kEdgeThreshold,
                         kEdgeThreshold, cv::BORDER_REFLECT_101);
    }
    pyramid_border_[level] = temp;
  }
}

std::vector<cv::KeyPoint> OrbExtractor::DistributeOctTree(
    const std::vector<cv::KeyPoint>& to_distribute, int min_x, int max_x, int min_y, int max_y,
    int n_features) const {
  std::vector<cv::KeyPoint> result;
  if (to_distribute.empty() || n_features <= 0) return result;
  const int n_ini = std::max(1, static_cast<int>(std::round(static_cast<float>(max_x - min_x) / (max_y - min_y))));
  const float h_x = static_cast<float>(max_x - min_x) / n_ini;
  int64_t next_order = 0;
  std::list<Node> nodes;
  std::vector<Node*> ini_nodes(n_ini);
  for (int i = 0; i < n_ini; ++i) {
    Node ni;
    ni.ul = cv::Point2i(static_cast<int>(h_x * i), 0);
    ni.ur = cv::Point2i(static_cast<int>(h_x * (i + 1)), 0);
    ni.bl = cv::Point2i(ni.ul.x, max_y - min_y);
    ni.br = cv::Point2i(ni.ur.x, max_y - min_y);
    ni.keys.reserve(to_distribute.size());
    ni.order = next_order++;
    nodes.push_back(ni);
    ini_nodes[i] = &nodes.back();
  }
  for (const cv::KeyPoint& kp : to_distribute) {
    const int idx = std::min(n_ini - 1, static_cast<int>(kp.pt.x / h_x));
    ini_nodes[idx]->keys.push_back(kp);
  }
  for (auto it = nodes.begin(); it != nodes.end();) {
    if (it->keys.size() == 1) {
      it->no_more = true;
      ++it;
    } else if (it->keys.empty()) {
      it = nodes.erase(it);
    } else {
      ++it;
    }
  }

  using SizeNode = std::pair<int, Node*>;
  std::vector<SizeNode> size_and_node;
  auto push_children = [&](Node* parent, int* n_to_expand) {
    Node n1, n2, n3, n4;
    parent->Divide(n1, n2, n3, n4);
    for (Node* n : {&n1, &n2, &n3, &n4}) {
      if (n->keys.empty()) continue;
      n->order = next_order++;
      nodes.push_front(std::move(*n));
      if (nodes.front().keys.size() > 1) {
        ++*n_to_expand;
        size_and_node.emplace_back(static_cast<int>(nodes.front().keys.size()), &nodes.front());
        nodes.front().it = nodes.begin();
      }
    }
  };

  bool finish = false;
  while (!finish) {
    int prev_size = static_cast<int>(nodes.size());
    int n_to_expand = 0;
    size_and_node.clear();
    for (auto it = nodes.begin(); it != nodes.end();) {
      if (it->no_more) {
        ++it;
        continue;
      }
      push_children(&*it, &n_to_expand);
      it = nodes.erase(it);
    }
    if (static_cast<int>(nodes.size()) >= n_features || static_cast<int>(nodes.size()) == prev_size) {
      finish = true;
    } else if (static_cast<int>(nodes.size()) + n_to_expand * 3 > n_features) {
      while (!finish) {
        prev_size = static_cast<int>(nodes.size());
        std::vector<SizeNode> prev = size_and_node;
        size_and_node.clear();
        // ORB-SLAM2 sorts (size, pointer) ascending and expands from the back; here equal sizes
        // are ordered by creation order.
        std::stable_sort(prev.begin(), prev.end(), [](const SizeNode& a, const SizeNode& b) {
          if (a.first != b.first) return a.first < b.first;
          return a.second->order < b.second->order;
        });
        for (int j = static_cast<int>(prev.size()) - 1; j >= 0; --j) {
          int dummy = 0;
          push_children(prev[j].second, &dummy);
          nodes.erase(prev[j].second->it);
          if (static_cast<int>(nodes.size()) >= n_features) break;
        }
        if (static_cast<int>(nodes.size()) >= n_features || static_cast<int>(nodes.size()) == prev_size)
          finish = true;
      }
    }
  }

  result.reserve(nodes.size());
  for (const Node& node : nodes) {
    const cv::KeyPoint* best = &node.keys[0];
    for (size_t k = 1; k < node.keys.size(); ++k)
      if (node.keys[k].response > best->response) best = &node.keys[k];
    result.push_back(*best);
  }
  return result;
}

namespace {

// The FAST grid of one pyramid level (ORBextractor::ComputeKeyPointsOctTree): 30 px cells inside
// the level's border, each cell 6 px wider for FAST's ring.
struct LevelGrid {
  int min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  int n_cols = 0, n_rows = 0, w_cell = 0, h_cell = 0;
};

LevelGrid MakeLevelGrid(const cv::Mat& img, int edge_threshold) {
  const float W = 30;
  LevelGrid g;
  g.min_x = g.min_y = edge_threshold - 3;
  g.max_x = img.cols - edge_threshold + 3;
  g.max_y = img.rows - edge_threshold + 3;
  const float width = static_cast<float>(g.max_x - g.min_x);
  const float height = static_cast<float>(g.max_y - g.min_y);
  if (width <= 0 || height <= 0) return g;  // n_rows = 0: no cells
  g.n_cols = std::max(1, static_cast<int>(width / W));
  g.n_rows = std::max(1, static_cast<int>(height / W));
  g.w_cell = static_cast<int>(std::ceil(width / g.n_cols));
  g.h_cell = static_cast<int>(std::ceil(height / g.n_rows));
  return g;
}

// FAST on the cells of grid row i, left to right, with the fallback threshold per empty cell;
// keypoints relative to (min_x, min_y) as ORB-SLAM2 collects them.
void FastRow(const cv::Mat& img, const LevelGrid& g, int i, int ini_th, int min_th,
             std::vector<cv::KeyPoint>* out) {
  const float ini_y = static_cast<float>(g.min_y + i * g.h_cell);
  float max_y = ini_y + g.h_cell + 6;
  if (ini_y >= g.max_y - 3) return;
  if (max_y > g.max_y) max_y = static_cast<float>(g.max_y);
  for (int j = 0; j < g.n_cols; ++j) {
    const float ini_x = static_cast<float>(g.min_x + j * g.w_cell);
    float max_x = ini_x + g.w_cell + 6;
    if (ini_x >= g.max_x - 6) continue;
    if (max_x > g.max_x) max_x = static_cast<float>(g.max_x);
    std::vector<cv::KeyPoint> cell;
    const cv::Mat sub = img.rowRange(static_cast<int>(ini_y), static_cast<int>(max_y))
                            .colRange(static_cast<int>(ini_x), static_cast<int>(max_x));
    cv::FAST(sub, cell, ini_th, true);
    if (cell.empty()) cv::FAST(sub, cell, min_th, true);
    for (cv::KeyPoint& kp : cell) {
      kp.pt.x += j * g.w_cell;
      kp.pt.y += i * g.h_cell;
      out->push_back(kp);
    }
  }
}

}  // namespace

void OrbExtractor::ComputeKeyPointsOctTree(std::vector<std::vector<cv::KeyPoint>>* all_keys) {
  const int n_levels = options_.n_levels;
  all_keys->assign(n_levels, {});
  std::vector<LevelGrid> grids;
  std::vector<int> first_row(static_cast<size_t>(n_levels) + 1, 0);  // task index of (level, row 0)
  for (int level = 0; level < n_levels; ++level) {
    grids.push_back(MakeLevelGrid(pyramid_[level], kEdgeThreshold));
    first_row[level + 1] = first_row[level] + grids[level].n_rows;
  }
  // FAST: one task per grid row of every level (the finest level holds most of the work, so
  // splitting by level alone leaves threads idle); each task writes only its own row slot.
  std::vector<std::vector<cv::KeyPoint>> rows(static_cast<size_t>(first_row[n_levels]));
  ParallelFor(first_row[n_levels], threads_, [&](int task) {
    const int level = static_cast<int>(std::upper_bound(first_row.begin(), first_row.end(), task) - first_row.begin()) - 1;
    FastRow(pyramid_[level], grids[level], task - first_row[level], options_.ini_th_fast, options_.min_th_fast,
            &rows[task]);
  });
  // Quadtree and orientation: one task per level, over its rows in grid order (row-major cells,
  // as ORB-SLAM2), so every level sees the same keypoint list for any thread count.
  ParallelFor(n_levels, threads_, [&](int level) {
    const LevelGrid& g = grids[level];
    if (g.n_rows == 0) return;
    std::vector<cv::KeyPoint> to_distribute;
    to_distribute.reserve(options_.n_features * 10);
    for (int r = first_row[level]; r < first_row[level + 1]; ++r)
      to_distribute.insert(to_distribute.end(), rows[r].begin(), rows[r].end());
    std::vector<cv::KeyPoint>& keys = (*all_keys)[level];
    keys = DistributeOctTree(to_distribute, g.min_x, g.max_x, g.min_y, g.max_y, features_per_level_[level]);
    const float scaled_patch = kPatchSize * scale_[level];
    const cv::Mat& img = pyramid_[level];
    for (cv::KeyPoint& kp : keys) {
      kp.pt.x += g.min_x;
      kp.pt.y += g.min_y;
      kp.octave = level;
      kp.size = scaled_patch;
      kp.angle = IcAngle(img, kp.pt, umax_);
    }
  });
}

void OrbExtractor::Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys,
                           cv::Mat* descriptors) {
  CV_Assert(grey.type() == CV_8U);
  ComputePyramid(grey);
  std::vector<std::vector<cv::KeyPoint>> all_keys;
  ComputeKeyPointsOctTree(&all_keys);
  keys->clear();
  for (const auto& level_keys : all_keys) keys->insert(keys->end(), level_keys.begin(), level_keys.end());
  const int n = static_cast<int>(keys->size());
  descriptors->create(n, 32, CV_8U);
  // rBRIEF on the blurred level images: the blur one task per level, then the descriptors in
  // fixed chunks of keys (each key writes only its own row), then keys to level-0 scale.
  std::vector<cv::Mat> blurred(static_cast<size_t>(options_.n_levels));
  ParallelFor(options_.n_levels, threads_, [&](int level) {
    if (all_keys[level].empty()) return;
    // The level is a view into its bordered buffer: BORDER_ISOLATED blurs it as the separate image
    // ORB-SLAM2 clones, without the copy.
    cv::GaussianBlur(pyramid_[level], blurred[level], cv::Size(7, 7), 2, 2,
                     cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED);
  });
  constexpr int kChunk = 128;
  ParallelFor((n + kChunk - 1) / kChunk, threads_, [&](int chunk) {
    const int end = std::min(n, (chunk + 1) * kChunk);
    for (int i = chunk * kChunk; i < end; ++i) {
      cv::KeyPoint& kp = (*keys)[i];
      OrbDescriptor(kp, blurred[kp.octave], descriptors->ptr<uchar>(i));
      if (kp.octave != 0) kp.pt *= scale_[kp.octave];
    }
  });
}

}  // namespace dynref::features
