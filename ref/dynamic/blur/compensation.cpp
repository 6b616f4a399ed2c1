#include "dynamic/blur/compensation.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <tuple>

namespace dynref::blur {

void CompensationOptions::Check() const {
  if (!(r_threshold > 0 && r_threshold <= 1)) throw std::invalid_argument("r_threshold must be in (0, 1]");
  if (history < 1 || history > 30) throw std::invalid_argument("history must be in 1..30");
  if (!(iou_found > 0 && iou_found <= 1)) throw std::invalid_argument("iou_found must be in (0, 1]");
  if (max_consecutive < 1) throw std::invalid_argument("max_consecutive must be >= 1");
}

cv::Point2d PredictCorner(const std::vector<CornerSample>& h, double t_c) {
  if (h.empty()) throw std::invalid_argument("PredictCorner: empty history");
  const double n = double(h.size());
  double st = 0, stt = 0, sx = 0, sy = 0, sxt = 0, syt = 0;
  for (const CornerSample& s : h) {
    const double tau = s.t - t_c;  // centred time
    st += tau, stt += tau * tau, sx += s.x, sy += s.y, sxt += s.x * tau, syt += s.y * tau;
  }
  const double den = n * stt - st * st;
  // One sample, or all at the same time: no slope; copy the newest corner in place.
  if (h.size() < 2 || !(std::abs(den) > 1e-18)) return {h.back().x, h.back().y};
  const double k1 = (n * sxt - sx * st) / den, k2 = (n * syt - sy * st) / den;
  const double b1 = (sx - k1 * st) / n, b2 = (sy - k2 * st) / n;
  return {b1, b2};  // the line at tau = 0, i.e. at t_c
}

double BoxIou(const cv::Rect& a, const cv::Rect& b) {
  const double i = (a & b).area(), u = double(a.area()) + double(b.area()) - i;
  return u > 0 ? i / u : 0.0;
}

MissedSegmentationCompensator::MissedSegmentationCompensator(const CompensationOptions& options, cv::Size image_size)
    : o_(options), size_(image_size) {
  o_.Check();
}

// Association (E3): greedy on box IoU, best pair first; ties by track then detection order.
// Returns the track of each person (-1: new); track_found per previous track.
std::vector<int> MissedSegmentationCompensator::Associate(const std::vector<PersonMask>& persons,
                                                          std::vector<bool>* track_found) const {
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t a = 0; a < tracks_.size(); ++a)
    for (size_t b = 0; b < persons.size(); ++b) {
      const double iou = BoxIou(tracks_[a].box, persons[b].box);
      if (iou >= o_.iou_found) pairs.emplace_back(iou, a, b);
    }
  std::stable_sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) {
    if (std::get<0>(x) != std::get<0>(y)) return std::get<0>(x) > std::get<0>(y);
    return std::make_pair(std::get<1>(x), std::get<2>(x)) < std::make_pair(std::get<1>(y), std::get<2>(y));
  });
  std::vector<int> track_of_person(persons.size(), -1);
  track_found->assign(tracks_.size(), false);
  for (const auto& [iou, a, b] : pairs) {
    if ((*track_found)[a] || track_of_person[b] >= 0) continue;
    (*track_found)[a] = true;
    track_of_person[b] = int(a);
  }
  return track_of_person;
}

// This frame's persons continue their associated track or start a new one.
void MissedSegmentationCompensator::ContinueTracks(double t, const std::vector<PersonMask>& persons,
                                                   const std::vector<int>& track_of_person, CompensationResult* res,
                                                   std::vector<Track>* next) {
  for (size_t b = 0; b < persons.size(); ++b) {
    Track tr;
    PersonAssociation as;
    if (track_of_person[b] >= 0) {
      tr = tracks_[size_t(track_of_person[b])];
      as.found = true;
      as.iou = BoxIou(tr.box, persons[b].box);
    } else {
      tr.id = next_id_++;
    }
    as.track = tr.id;
    res->association.push_back(as);
    tr.history.push_back({double(persons[b].box.x), double(persons[b].box.y), t});
    while (int(tr.history.size()) > o_.history) tr.history.pop_front();
    tr.mask = persons[b].mask;
    tr.box = persons[b].box;
    tr.anchor = persons[b].box.tl();
    tr.consecutive = 0;
    res->boxes.push_back(tr.box);
    next->push_back(std::move(tr));
  }
}

// Compensation: each previous track not found is pasted at its predicted corner (E2) unless it
// was pasted too often or leaves the image (then it ends, with the reason).
void MissedSegmentationCompensator::PasteMissed(double t, const std::vector<bool>& track_found,
                                                CompensationResult* res, std::vector<Track>* next) const {
  const auto drop = [&](size_t a, DroppedTrack::Why why) { res->dropped.push_back({tracks_[a].id, why}); };
  const cv::Rect image(0, 0, size_.width, size_.height);
  for (size_t a = 0; a < tracks_.size(); ++a) {
    if (track_found[a]) continue;
    if (tracks_[a].consecutive >= o_.max_consecutive) {
      drop(a, DroppedTrack::kMaxConsecutive);
      continue;
    }
    Track tr = tracks_[a];
    const std::vector<CornerSample> h(tr.history.begin(), tr.history.end());
    const cv::Point2d to = PredictCorner(h, t);
    const int dx = int(std::lround(to.x - tr.anchor.x)), dy = int(std::lround(to.y - tr.anchor.y));
    // Translate the last mask by (dx, dy), clipped to the image.
    cv::Mat moved = cv::Mat::zeros(size_, CV_8U);
    const cv::Rect src = image & (image - cv::Point(dx, dy));
    if (src.area() > 0) tr.mask(src).copyTo(moved(src + cv::Point(dx, dy)));
    const int moved_px = cv::countNonZero(moved);
    if (moved_px == 0) {  // predicted out of the image: the person left
      drop(a, DroppedTrack::kOutsideImage);
      continue;
    }
    PastedMask pm;
    pm.track = tr.id;
    pm.samples = int(h.size());
    pm.history = h;
    pm.from = {double(tr.anchor.x), double(tr.anchor.y)};
    pm.to = to;
    pm.shift = {dx, dy};
    pm.moved_px = moved_px;
    const cv::Mat added = moved & ~res->mask;
    pm.pasted_px = cv::countNonZero(added);
    res->compensated |= added;
    res->mask |= moved;
    // E2: the history continues with the compensated state, so repeated drop-outs are bridged.
    tr.mask = moved;
    tr.box = cv::boundingRect(moved);
    tr.anchor += cv::Point(dx, dy);
    tr.history.push_back({to.x, to.y, t});
    while (int(tr.history.size()) > o_.history) tr.history.pop_front();
    ++tr.consecutive;
    pm.box = tr.box;
    pm.consecutive = tr.consecutive;
    res->pasted.push_back(std::move(pm));
    res->boxes.push_back(tr.box);
    next->push_back(std::move(tr));
  }
}

CompensationResult MissedSegmentationCompensator::Process(double t, const std::vector<PersonMask>& persons,
                                                          bool enabled) {
  CompensationResult res;
  res.mask = cv::Mat::zeros(size_, CV_8U);
  res.compensated = cv::Mat::zeros(size_, CV_8U);
  for (const PersonMask& p : persons) res.mask |= p.mask;
  res.area_now = cv::countNonZero(res.mask);
  res.area_before = last_area_;

  std::vector<bool> track_found;
  const std::vector<int> track_of_person = Associate(persons, &track_found);
  std::vector<Track> next;
  ContinueTracks(t, persons, track_of_person, &res, &next);

  // r = A_c / A_{c-1} over all persons (E1); A_{c-1} = 0: undefined, no compensation.
  if (last_area_ > 0) res.r = res.area_now / last_area_;
  res.triggered = enabled && res.r >= 0 && res.r < o_.r_threshold;
  // Previous tracks not found end here unless pasted (trace: why).
  if (!res.triggered)
    for (size_t a = 0; a < tracks_.size(); ++a)
      if (!track_found[a])
        res.dropped.push_back({tracks_[a].id, enabled ? DroppedTrack::kNotTriggered : DroppedTrack::kCompensationOff});
  if (res.triggered) PasteMissed(t, track_found, &res, &next);
  std::stable_sort(next.begin(), next.end(), [](const Track& x, const Track& y) { return x.id < y.id; });
  tracks_ = std::move(next);
  last_area_ = cv::countNonZero(res.mask);
  return res;
}

}  // namespace dynref::blur
