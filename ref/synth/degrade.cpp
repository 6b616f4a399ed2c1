#include "synth/degrade.h"

#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "io/coco_classes.h"
#include "synth/humanoid.h"
#include "synth/texture.h"

namespace dynref::synth {
namespace {

struct Stats {
  int area = 0;
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  double depth_sum = 0;
  double x_sum = 0, y_sum = 0;
};

std::map<int, Stats> InstanceStats(const GtFrame& gt) {
  std::map<int, Stats> out;
  for (int y = 0; y < gt.instance_ids.rows; ++y) {
    const uint16_t* row = gt.instance_ids.ptr<uint16_t>(y);
    const float* z = gt.depth_m.empty() ? nullptr : gt.depth_m.ptr<float>(y);
    for (int x = 0; x < gt.instance_ids.cols; ++x) {
      if (row[x] == 0) continue;
      Stats& s = out[row[x]];
      ++s.area;
      s.x0 = std::min(s.x0, x), s.x1 = std::max(s.x1, x), s.y0 = std::min(s.y0, y), s.y1 = std::max(s.y1, y);
      if (z) s.depth_sum += double(z[x]);
      s.x_sum += x, s.y_sum += y;
    }
  }
  return out;
}

// Confusable COCO classes (what a detector plausibly outputs instead).
int Confuse(int coco_id, Rng& rng) {
  switch (coco_id) {
    case 0: return rng.Bernoulli(0.5) ? 77 : 27;   // person -> teddy_bear / tie
    case 56: return rng.Bernoulli(0.5) ? 57 : 13;  // chair -> sofa / bench
    case 62: return 63;                            // tvmonitor -> laptop
    case 63: return 62;                            // laptop -> tvmonitor
    case 66: return 63;                            // keyboard -> laptop
    case 73: return 65;                            // book -> remote
    case 60: return 59;                            // diningtable -> bed
    case 41: return 39;                            // cup -> bottle
    case 58: return 46;                            // pottedplant -> broccoli
    case 64: return 65;                            // mouse -> remote
    default: return coco_id;
  }
}

struct Record {
  DetectedInstance det;
  cv::Mat mask;   // full-size CV_8U, 255 inside
  double depth = 0;
  int gt_id = 0;
  bool false_positive = false;
};

cv::Mat JitterBoundary(const cv::Mat& mask, int jitter_px, uint32_t key, Rng& rng) {
  if (jitter_px <= 0) return mask;
  const cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * jitter_px + 1, 2 * jitter_px + 1));
  cv::Mat dil, ero;
  cv::dilate(mask, dil, k);
  cv::erode(mask, ero, k);
  const float threshold = float(rng.Uniform(0.35, 0.65));  // < 0.5 grows, > 0.5 shrinks on average
  cv::Mat out = ero.clone();
  for (int y = 0; y < mask.rows; ++y) {
    const uint8_t* d = dil.ptr<uint8_t>(y);
    const uint8_t* e = ero.ptr<uint8_t>(y);
    uint8_t* o = out.ptr<uint8_t>(y);
    for (int x = 0; x < mask.cols; ++x)
      if (d[x] && !e[x] && ValueNoise(float(x) / 7.f, float(y) / 7.f, key) > threshold) o[x] = 255;
  }
  return out;
}

void BoxFromMask(const cv::Mat& mask, int jitter, Rng& rng, DetectedInstance* d) {
  const cv::Rect r = cv::boundingRect(mask);
  const auto j = [&] { return jitter > 0 ? double(rng.UniformInt(-jitter, jitter)) : 0.0; };
  // Jitter never pushes a box corner out of the image (a 1-px mask on the right edge jittered by
  // +1 gave x_min = width > x_max, a record every reader rightly refuses).
  d->x_min = std::clamp(r.x + j(), 0.0, double(mask.cols - 1));
  d->y_min = std::clamp(r.y + j(), 0.0, double(mask.rows - 1));
  d->x_max = std::min(double(mask.cols - 1), std::max(d->x_min, r.x + r.width - 1 + j()));
  d->y_max = std::min(double(mask.rows - 1), std::max(d->y_min, r.y + r.height - 1 + j()));
}

// Blur streak per instance: centroid displacement since the previous frame (px/frame) times
// the exposure in frame intervals; 0 without blur or without a previous frame. Replaces
// *centroids with this frame's.
std::map<int, double> DegradeBlurStreaks(const std::map<int, Stats>& stats, bool consecutive, double exposure_frames,
                                         double blur_max_px, std::map<int, cv::Point2d>* centroids) {
  std::map<int, double> blur_px;
  std::map<int, cv::Point2d> centroid;
  for (const auto& [id, s] : stats) {
    const cv::Point2d c(s.x_sum / s.area, s.y_sum / s.area);
    const auto prev = centroids->find(id);
    if (consecutive && prev != centroids->end())
      blur_px[id] = std::min(blur_max_px, cv::norm(c - prev->second) * exposure_frames);
    centroid.emplace(id, c);
  }
  *centroids = std::move(centroid);
  return blur_px;
}

// Missed bursts (stay / enter, more likely under blur streak L) and small-instance misses;
// true when the instance is not detected this frame.
bool DegradeDrawMissed(const DegradeProfile& p, const Stats& s, double L, bool* missed, Rng& rng, bool* small_miss) {
  if (*missed) {
    *missed = rng.Bernoulli(p.miss_stay);
  } else {
    const double p_blur = std::min(p.blur_drop_max, p.blur_drop_per_px * L);
    *missed = rng.Bernoulli(L > 0 ? 1.0 - (1.0 - p.miss_enter) * (1.0 - p_blur) : p.miss_enter);
  }
  *small_miss = s.area < p.small_area_px && rng.Bernoulli(p.small_miss);
  return *missed || *small_miss;
}

// The detected mask of instance id: blur shrink, dropped person limbs, jittered boundary.
cv::Mat DegradeMask(const DegradeProfile& p, const GtFrame& gt, int id, const InstanceLabel& label, double L, Rng& rng,
                    std::vector<DegradeEvent>* events) {
  cv::Mat mask = gt.instance_ids == id;
  if (L > 0 && rng.Bernoulli(std::min(p.blur_shrink_max, p.blur_shrink_per_px * L))) {
    const int radius = int(std::lround(p.blur_shrink_depth * L));
    if (radius > 0) {
      cv::erode(mask, mask, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1)));
      events->push_back({id, "shrunk", L, radius});
    }
  }
  if (label.coco_id == 0 && rng.Bernoulli(p.limb_drop)) {
    const int limbs[4] = {kForearmL, kForearmR, kShinL, kShinR};
    const int limb = limbs[rng.UniformInt(0, 3)];
    mask.setTo(0, gt.body_part == limb);
    if (rng.Bernoulli(0.3)) mask.setTo(0, gt.body_part == limb - 2);  // upper arm / thigh too
  }
  return JitterBoundary(mask, p.boundary_jitter_px, uint32_t(rng.NextU64()), rng);
}

// One false positive on a large static instance (painted first: any true detection overlapping it wins).
void DegradeFalsePositive(const DegradeProfile& p, const GtFrame& gt, const std::map<int, InstanceLabel>& labels,
                          const std::vector<int>& static_candidates, Rng& rng, std::vector<Record>* recs) {
  if (static_candidates.empty() || !rng.Bernoulli(p.false_positive)) return;
  Record r;
  r.gt_id = static_candidates[size_t(rng.UniformInt(0, int64_t(static_candidates.size()) - 1))];
  r.false_positive = true;
  r.depth = 1e9;  // painted first: any true detection overlapping it wins
  r.mask = JitterBoundary(gt.instance_ids == r.gt_id, p.boundary_jitter_px, uint32_t(rng.NextU64()), rng);
  r.det.class_id = rng.Bernoulli(0.6) ? 0 : Confuse(labels.at(r.gt_id).coco_id, rng);
  r.det.class_name = CocoClassName(r.det.class_id);
  r.det.confidence = rng.Uniform(0.25, 0.45);
  if (cv::countNonZero(r.mask) > 0) recs->push_back(std::move(r));
}

// Paints the records far to near into the frame's id image; a fully overpainted one is dropped
// (an event unless it is the false positive), the others get their box.
FrameDetections DegradePaint(const DegradeProfile& p, const GtFrame& gt, std::vector<Record>& recs,
                             std::map<int, double>& blur_px, Rng& rng, std::vector<DegradeEvent>* events) {
  FrameDetections f;
  f.stamp_text = gt.stamp_text;
  f.instance_ids = cv::Mat::zeros(gt.instance_ids.size(), CV_16U);
  std::vector<size_t> order(recs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return recs[a].depth != recs[b].depth ? recs[a].depth > recs[b].depth : recs[a].gt_id < recs[b].gt_id;
  });
  for (size_t i : order) f.instance_ids.setTo(recs[i].det.id, recs[i].mask);
  for (Record& r : recs) {
    if (cv::countNonZero(f.instance_ids == r.det.id) == 0) {  // fully overpainted
      if (!r.false_positive) events->push_back({r.gt_id, "overpainted", blur_px.count(r.gt_id) ? blur_px[r.gt_id] : 0.0, 0});
      continue;
    }
    BoxFromMask(f.instance_ids == r.det.id, p.box_jitter_px, rng, &r.det);
    r.det.has_mask = true;
    f.instances.push_back(r.det);
  }
  std::sort(f.instances.begin(), f.instances.end(),
            [](const DetectedInstance& a, const DetectedInstance& b) { return a.id < b.id; });
  return f;
}

}  // namespace

DegradeProfile ProfileFor(const std::string& mode) {
  DegradeProfile p;
  p.name = mode;
  if (mode == "ideal") return p;
  if (mode == "yolo-like") {
    p.miss_enter = 0.03, p.miss_stay = 0.7, p.small_miss = 0.15;
    p.blur_drop_per_px = 0.015, p.blur_drop_max = 0.4;
    p.blur_shrink_per_px = 0.05, p.blur_shrink_max = 0.8, p.blur_shrink_depth = 0.5;
    p.min_area_px = 300, p.boundary_jitter_px = 4, p.limb_drop = 0.15, p.false_positive = 0.08;
    p.confusion = 0.05, p.person_confusion = 0.01, p.box_jitter_px = 3, p.conf_lo = 0.5, p.conf_hi = 0.95;
    return p;
  }
  if (mode == "sparseinst-like") {
    p.miss_enter = 0.02, p.miss_stay = 0.6, p.small_miss = 0.1;
    p.blur_drop_per_px = 0.01, p.blur_drop_max = 0.3;
    p.blur_shrink_per_px = 0.05, p.blur_shrink_max = 0.8, p.blur_shrink_depth = 0.5;
    p.min_area_px = 200, p.boundary_jitter_px = 2, p.limb_drop = 0.25, p.false_positive = 0.05;
    p.confusion = 0.03, p.person_confusion = 0.005, p.box_jitter_px = 1, p.conf_lo = 0.55, p.conf_hi = 0.98;
    return p;
  }
  throw InputError("--detections", "unknown mode '" + mode + "' (none, ideal, yolo-like, sparseinst-like, all)");
}

FrameDetections GtDetections(const GtFrame& gt, const std::map<int, InstanceLabel>& labels) {
  FrameDetections f;
  f.stamp_text = gt.stamp_text;
  f.instance_ids = gt.instance_ids;
  for (const auto& [id, s] : InstanceStats(gt)) {
    const auto it = labels.find(id);
    DetectedInstance d;
    d.id = id;
    d.class_id = it == labels.end() ? -1 : it->second.coco_id;
    d.class_name = it == labels.end() ? "unknown" : it->second.class_name;
    d.confidence = 1.0;
    d.x_min = s.x0, d.y_min = s.y0, d.x_max = s.x1, d.y_max = s.y1;
    d.has_mask = true;
    f.instances.push_back(d);
  }
  return f;
}

Degrader::Degrader(const DegradeProfile& profile, const std::map<int, InstanceLabel>& labels, uint64_t seed,
                   double blur_exposure_frames)
    : p_(profile), labels_(labels), seed_(seed), blur_exposure_frames_(blur_exposure_frames) {}

std::string DegradeEventsLine(const std::string& stamp, const std::vector<DegradeEvent>& events) {
  std::string line = stamp;
  for (const DegradeEvent& e : events) {
    char buf[96];
    std::snprintf(buf, sizeof buf, " %d:%s:%.1f", e.gt_id, e.what.c_str(), e.blur_px);
    line += buf;
    if (e.what == "shrunk") line += ":" + std::to_string(e.shrink_px);
  }
  return line + "\n";
}

FrameDetections Degrader::Apply(int frame_index, const GtFrame& gt) {
  Rng rng(seed_, "synth.detections." + p_.name + "." + std::to_string(frame_index));
  const auto stats = InstanceStats(gt);
  events_.clear();
  const bool consecutive = blur_exposure_frames_ > 0 && previous_frame_ == frame_index - 1;
  std::map<int, double> blur_px = DegradeBlurStreaks(stats, consecutive, blur_exposure_frames_, p_.blur_max_px, &centroid_);
  previous_frame_ = frame_index;
  std::vector<Record> recs;
  std::vector<int> static_candidates;
  for (const auto& [id, s] : stats) {
    const auto lit = labels_.find(id);
    if (lit == labels_.end() || lit->second.coco_id < 0) continue;  // detectors only know COCO classes
    const InstanceLabel& label = lit->second;
    if (!label.prior_dynamic && s.area > 2000) static_candidates.push_back(id);
    if (s.area < p_.min_area_px) continue;
    const auto bit = blur_px.find(id);
    const double L = bit == blur_px.end() ? 0.0 : bit->second;
    bool& missed = missed_[id];
    bool small_miss = false;
    if (DegradeDrawMissed(p_, s, L, &missed, rng, &small_miss)) {
      events_.push_back({id, missed ? "missed" : "small-missed", L, 0});
      continue;
    }
    Record r;
    r.gt_id = id;
    r.depth = s.depth_sum / s.area;
    r.mask = DegradeMask(p_, gt, id, label, L, rng, &events_);
    if (cv::countNonZero(r.mask) == 0) continue;
    r.det.class_id = label.coco_id;
    if (rng.Bernoulli(label.coco_id == 0 ? p_.person_confusion : p_.confusion)) r.det.class_id = Confuse(label.coco_id, rng);
    r.det.class_name = CocoClassName(r.det.class_id);
    r.det.confidence = p_.name == "ideal" ? 1.0 : rng.Uniform(p_.conf_lo, p_.conf_hi) * (s.area < p_.small_area_px ? 0.8 : 1.0);
    recs.push_back(std::move(r));
  }
  DegradeFalsePositive(p_, gt, labels_, static_candidates, rng, &recs);
  // Frame-local ids: ideal keeps the GT ids; degraded modes number 1..n (GT id order, false
  // positive last) as a network would.
  for (size_t i = 0; i < recs.size(); ++i) recs[i].det.id = p_.name == "ideal" ? recs[i].gt_id : int(i + 1);
  FrameDetections f = DegradePaint(p_, gt, recs, blur_px, rng, &events_);
  std::stable_sort(events_.begin(), events_.end(),
                   [](const DegradeEvent& a, const DegradeEvent& b) { return a.gt_id < b.gt_id; });
  return f;
}

}  // namespace dynref::synth
