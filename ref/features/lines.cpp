#include "features/lines.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/line_descriptor.hpp>
#include <stdexcept>

#include "plugins/opencv_extra_abi.h"

namespace dynref::features {

void LineOptions::Check() const {
  if (min_length_px < 2) throw std::invalid_argument("min_length_px must be >= 2");
  if (!(distance_threshold_px > 0)) throw std::invalid_argument("distance_threshold_px must be > 0");
  if (!(parallel_deg > 0 && parallel_deg < 90)) throw std::invalid_argument("parallel_deg must be in (0, 90)");
  if (max_lines < 1) throw std::invalid_argument("max_lines must be >= 1");
}

double LineAngleDiff(double a, double b) {
  double d = std::fmod(std::fabs(a - b), M_PI);
  return d > M_PI / 2 ? M_PI - d : d;
}

Eigen::Vector3d LineThrough(const Eigen::Vector2d& s, const Eigen::Vector2d& e) {
  const Eigen::Vector3d l = Eigen::Vector3d(s.x(), s.y(), 1.0).cross(Eigen::Vector3d(e.x(), e.y(), 1.0));
  const double n = std::hypot(l.x(), l.y());
  return n > 0 ? Eigen::Vector3d(l / n) : Eigen::Vector3d::Zero();
}

void GroupParallel(std::vector<Segment>* segments, double parallel_deg) {
  std::vector<Segment>& segs = *segments;
  const double tau = parallel_deg * M_PI / 180.0;
  const int n = static_cast<int>(segs.size());
  // Union-find over the "parallel" relation; O(n^2) on <= max_lines segments.
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (LineAngleDiff(segs[i].angle, segs[j].angle) < tau) {
        const int a = find(i), b = find(j);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
  std::vector<int> group_of_root(n, -1);
  int groups = 0;
  for (int i = 0; i < n; ++i) {
    const int r = find(i);
    if (group_of_root[r] < 0) group_of_root[r] = groups++;
    segs[i].group = group_of_root[r];
  }
  for (int i = 0; i < n; ++i) {
    int best = -1;
    for (int j = 0; j < n; ++j) {
      if (j == i || segs[j].group != segs[i].group) continue;
      if (best < 0) { best = j; continue; }
      const double dj = LineAngleDiff(segs[i].angle, segs[j].angle);
      const double db = LineAngleDiff(segs[i].angle, segs[best].angle);
      if (dj < db || (dj == db && segs[j].length > segs[best].length)) best = j;
    }
    segs[i].companion = best;
  }
}

SegmentSet DetectSegments(const cv::Mat& grey, const LineOptions& o) {
  o.Check();
  if (grey.type() != CV_8U) throw std::invalid_argument("DetectSegments needs a CV_8U grey image");
  std::vector<cv::Vec4f> raw;
  // ximgproc's FastLineDetector, run in the OpenCV module (plugins/opencv_extra_abi.h).
  plugins::OpenCvExtraModule().fast_lines(grey, o.min_length_px, static_cast<float>(o.distance_threshold_px),
                                          o.canny_low, o.canny_high, 3, false, raw);
  std::vector<Segment> segs;
  segs.reserve(raw.size());
  for (const cv::Vec4f& r : raw) {
    Segment s;
    s.s = {r[0], r[1]};
    s.e = {r[2], r[3]};
    s.length = (s.e - s.s).norm();
    if (s.length < o.min_length_px) continue;
    double a = std::atan2(s.e.y() - s.s.y(), s.e.x() - s.s.x());
    if (a < 0) a += M_PI;
    if (a >= M_PI) a -= M_PI;
    s.angle = a;
    segs.push_back(s);
  }
  // Longest first (stable: FLD's order breaks ties), at most max_lines.
  std::vector<int> order(segs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return segs[a].length > segs[b].length; });
  if (static_cast<int>(order.size()) > o.max_lines) order.resize(static_cast<size_t>(o.max_lines));
  SegmentSet out;
  for (int i : order) out.segments.push_back(segs[static_cast<size_t>(i)]);
  if (out.segments.empty()) {
    out.descriptors = cv::Mat(0, 32, CV_8U);
    return out;
  }
  // LBD on octave 0 keylines built from the segments.
  std::vector<cv::line_descriptor::KeyLine> keylines;
  for (size_t i = 0; i < out.segments.size(); ++i) {
    const Segment& s = out.segments[i];
    cv::line_descriptor::KeyLine k;
    k.startPointX = k.sPointInOctaveX = static_cast<float>(s.s.x());
    k.startPointY = k.sPointInOctaveY = static_cast<float>(s.s.y());
    k.endPointX = k.ePointInOctaveX = static_cast<float>(s.e.x());
    k.endPointY = k.ePointInOctaveY = static_cast<float>(s.e.y());
    k.lineLength = static_cast<float>(s.length);
    k.angle = static_cast<float>(std::atan2(s.e.y() - s.s.y(), s.e.x() - s.s.x()));
    k.octave = 0;
    k.class_id = static_cast<int>(i);
    k.pt = cv::Point2f(static_cast<float>((s.s.x() + s.e.x()) / 2), static_cast<float>((s.s.y() + s.e.y()) / 2));
    k.response = static_cast<float>(s.length / std::max(grey.cols, grey.rows));
    k.size = k.lineLength;
    k.numOfPixels = static_cast<int>(std::lround(s.length));
    keylines.push_back(k);
  }
  const cv::Ptr<cv::line_descriptor::BinaryDescriptor> lbd = cv::line_descriptor::BinaryDescriptor::createBinaryDescriptor();
  cv::Mat desc;
  lbd->compute(grey, keylines, desc);
  // compute() may drop keylines it cannot describe; keep the described ones by class_id.
  std::vector<Segment> kept;
  cv::Mat rows(0, 32, CV_8U);
  for (size_t k = 0; k < keylines.size() && static_cast<int>(k) < desc.rows; ++k) {
    kept.push_back(out.segments[static_cast<size_t>(keylines[k].class_id)]);
    rows.push_back(desc.row(static_cast<int>(k)));
  }
  out.segments = std::move(kept);
  out.descriptors = rows;
  GroupParallel(&out.segments, o.parallel_deg);
  return out;
}

}  // namespace dynref::features
