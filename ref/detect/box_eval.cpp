#include "detect/box_eval.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace dynref::detect {

std::vector<HandBox> ReadHandBoxes(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open file");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(!l.empty() && l.back() == '\r' ? l.substr(0, l.size() - 1) : l);
  std::vector<HandBox> out;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    if (l.empty() || l[0] == '#') continue;
    std::istringstream s(l);
    HandBox b;
    std::string extra;
    if (!(s >> b.stamp_text >> b.class_name >> b.label >> b.x_min >> b.y_min >> b.x_max >> b.y_max) || (s >> extra))
      throw InputError(path, int(i + 1), "expected 'rgb_stamp class label x_min y_min x_max y_max'");
    if (!(b.x_max >= b.x_min && b.y_max >= b.y_min)) throw InputError(path, int(i + 1), "box has max < min");
    out.push_back(b);
  }
  return out;
}

double InclusiveBoxIou(double ax0, double ay0, double ax1, double ay1, double bx0, double by0, double bx1,
                       double by1) {
  const double iw = std::min(ax1, bx1) - std::max(ax0, bx0) + 1, ih = std::min(ay1, by1) - std::max(ay0, by0) + 1;
  if (iw <= 0 || ih <= 0) return 0.0;
  const double inter = iw * ih;
  const double ua = (ax1 - ax0 + 1) * (ay1 - ay0 + 1) + (bx1 - bx0 + 1) * (by1 - by0 + 1) - inter;
  return inter / ua;
}

MatchCounts MatchAgainstHandBoxes(const std::map<std::string, FrameDetections>& frames,
                                  const std::vector<HandBox>& truth, const std::string& class_name,
                                  double min_confidence, double iou) {
  std::map<std::string, std::vector<const HandBox*>> by_frame;
  MatchCounts c;
  for (const HandBox& b : truth)
    if (b.class_name == class_name) {
      by_frame[b.stamp_text].push_back(&b);
      ++c.truth;
    }
  for (const auto& [stamp, det] : frames) {
    std::vector<const DetectedInstance*> kept;
    for (const DetectedInstance& d : det.instances)
      if (d.class_name == class_name && d.confidence >= min_confidence) kept.push_back(&d);
    std::sort(kept.begin(), kept.end(), [](const DetectedInstance* a, const DetectedInstance* b) {  // ids unique
      return a->confidence != b->confidence ? a->confidence > b->confidence : a->id < b->id;
    });
    c.detections += int(kept.size());
    std::vector<const HandBox*>& boxes = by_frame[stamp];
    std::vector<bool> used(boxes.size(), false);
    for (const DetectedInstance* d : kept) {
      int best = -1;
      double best_iou = iou;
      for (size_t j = 0; j < boxes.size(); ++j) {
        if (used[j]) continue;
        const HandBox& h = *boxes[j];
        const double v = InclusiveBoxIou(d->x_min, d->y_min, d->x_max, d->y_max, h.x_min, h.y_min, h.x_max, h.y_max);
        if (v >= best_iou && (best < 0 || v > best_iou)) {
          best = int(j);
          best_iou = v;
        }
      }
      if (best >= 0) {
        used[size_t(best)] = true;
        ++c.matched;
      }
    }
  }
  return c;
}

std::map<std::string, ScoreSummary> SummariseScores(const std::map<std::string, FrameDetections>& frames,
                                                    const std::vector<double>& cuts) {
  std::map<std::string, std::vector<double>> scores;
  for (const auto& [stamp, det] : frames)
    for (const DetectedInstance& d : det.instances) scores[d.class_name].push_back(d.confidence);
  std::map<std::string, ScoreSummary> out;
  for (auto& [name, v] : scores) {
    std::sort(v.begin(), v.end());
    ScoreSummary s;
    s.count = int(v.size());
    const auto q = [&v](double p) { return v[size_t(p * double(v.size() - 1) + 0.5)]; };
    s.min = v.front();
    s.q25 = q(0.25);
    s.median = q(0.5);
    s.q75 = q(0.75);
    s.max = v.back();
    for (double cut : cuts) s.at_least.push_back(int(v.end() - std::lower_bound(v.begin(), v.end(), cut)));
    out[name] = s;
  }
  return out;
}

}  // namespace dynref::detect
