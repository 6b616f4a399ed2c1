#include "detect/temporal_links.h"

#include <algorithm>
#include <stdexcept>

namespace dynref::detect {

void TemporalOptions::Check() const {
  if (max_gap < 0 || max_gap > 30) throw std::invalid_argument("max_gap must be in 0..30");
  if (!(iou_link > 0 && iou_link <= 1)) throw std::invalid_argument("iou_link must be in (0, 1]");
  if (history < 1 || history > 30) throw std::invalid_argument("history must be in 1..30");
}

cv::Point2d PredictCornerLsq(const std::vector<cv::Point3d>& s, double t_c) {
  if (s.empty()) throw std::invalid_argument("PredictCornerLsq: no samples");
  const double n = double(s.size());
  double st = 0, stt = 0, sx = 0, sy = 0, stx = 0, sty = 0;
  for (const cv::Point3d& p : s) {
    const double tau = p.z - t_c;
    st += tau;
    stt += tau * tau;
    sx += p.x;
    sy += p.y;
    stx += tau * p.x;
    sty += tau * p.y;
  }
  const double den = n * stt - st * st;
  if (s.size() < 2 || den <= 0) return {s.back().x, s.back().y};
  return {(stt * sx - st * stx) / den, (stt * sy - st * sty) / den};  // intercepts at tau = 0
}

namespace {

double Iou(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double inter = (a & b).area();
  const double uni = a.area() + b.area() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

cv::Rect2d BoxOf(const DetectedInstance& d) { return {d.x_min, d.y_min, d.x_max - d.x_min, d.y_max - d.y_min}; }

}  // namespace

TemporalLinker::TemporalLinker(const TemporalOptions& options, cv::Size image_size) : o_(options), size_(image_size) {
  o_.Check();
}

FrameDetections TemporalLinker::Process(const FrameDetections& in, double stamp_s, std::vector<TrackLink>* links) {
  FrameDetections out = in;
  if (links) links->clear();
  // Candidate pairs (IoU >= iou_link, same class), best first; ties: lower track, lower instance.
  struct Pair {
    double iou;
    int track;
    size_t inst;
  };
  std::vector<Pair> pairs;
  for (size_t i = 0; i < in.instances.size(); ++i) {
    const DetectedInstance& d = in.instances[i];
    if (!o_.class_ids.count(d.class_id)) continue;
    for (const auto& [id, t] : tracks_)
      if (t.class_id == d.class_id) {
        const double v = Iou(t.box, BoxOf(d));
        if (v >= o_.iou_link) pairs.push_back({v, id, i});
      }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    if (a.iou != b.iou) return a.iou > b.iou;
    return a.track != b.track ? a.track < b.track : a.inst < b.inst;
  });
  std::map<size_t, int> track_of;  // instance index -> track
  std::set<int> matched;
  for (const Pair& p : pairs)
    if (!matched.count(p.track) && !track_of.count(p.inst)) {
      matched.insert(p.track);
      track_of[p.inst] = p.track;
    }
  for (size_t i = 0; i < in.instances.size(); ++i) {
    const DetectedInstance& d = in.instances[i];
    if (!o_.class_ids.count(d.class_id)) continue;
    if (!track_of.count(i)) {
      Track t;
      t.id = next_track_++;
      t.class_id = d.class_id;
      t.class_name = d.class_name;
      tracks_[t.id] = t;
      track_of[i] = t.id;
      matched.insert(t.id);
    }
    Track& t = tracks_[track_of[i]];
    t.missed = 0;
    t.confidence = d.confidence;
    t.box = BoxOf(d);
    t.corners.push_back({d.x_min, d.y_min, stamp_s});
    if (int(t.corners.size()) > o_.history) t.corners.erase(t.corners.begin());
    if (links) links->push_back({d.id, t.id, false});
  }
  // Tracks not found: carried along the corner line for max_gap frames, then ended.
  int next_id = 0;
  for (const DetectedInstance& d : in.instances) next_id = std::max(next_id, d.id);
  const cv::Rect2d image(0, 0, size_.width - 1, size_.height - 1);
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    Track& t = it->second;
    if (matched.count(t.id)) {
      ++it;
      continue;
    }
    if (++t.missed > o_.max_gap) {
      it = tracks_.erase(it);
      continue;
    }
    const cv::Point2d c = PredictCornerLsq(t.corners, stamp_s);
    const cv::Rect2d box = cv::Rect2d(c.x, c.y, t.box.width, t.box.height) & image;
    if (box.area() <= 0 || next_id >= 65535) {
      it = tracks_.erase(it);
      continue;
    }
    DetectedInstance d;
    d.id = ++next_id;
    d.class_id = t.class_id;
    d.class_name = t.class_name;
    d.confidence = t.confidence;
    d.x_min = box.x;
    d.y_min = box.y;
    d.x_max = box.x + box.width;
    d.y_max = box.y + box.height;
    d.has_mask = false;
    out.instances.push_back(d);
    ++carried_total_;
    if (links) links->push_back({d.id, t.id, true});
    ++it;
  }
  return out;
}

}  // namespace dynref::detect
