#include "detect/candidates.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "core/stable_sort.h"
#include "io/coco_classes.h"

namespace dynref::detect {

double BoxIou(const Candidate& a, const Candidate& b) {
  const double ix = std::max(0.0, std::min(a.x_max, b.x_max) - std::max(a.x_min, b.x_min));
  const double iy = std::max(0.0, std::min(a.y_max, b.y_max) - std::max(a.y_min, b.y_min));
  const double inter = ix * iy;
  const double area_a = std::max(0.0, a.x_max - a.x_min) * std::max(0.0, a.y_max - a.y_min);
  const double area_b = std::max(0.0, b.x_max - b.x_min) * std::max(0.0, b.y_max - b.y_min);
  const double uni = area_a + area_b - inter;
  return uni > 0 ? inter / uni : 0.0;
}

std::vector<Candidate> PerClassNms(std::vector<Candidate> candidates, double iou_threshold,
                                   int max_detections) {
  // Descending score, then class, then anchor: a total order for distinct (class, anchor).
  StableSortBy(candidates, [](const Candidate& c) { return std::make_tuple(-c.score, c.class_id, c.anchor); });
  std::map<int, std::vector<Candidate>> kept_by_class;
  std::vector<Candidate> kept;
  for (const Candidate& c : candidates) {
    auto& same_class = kept_by_class[c.class_id];
    bool suppressed = false;
    for (const Candidate& k : same_class)
      if (BoxIou(k, c) > iou_threshold) {
        suppressed = true;
        break;
      }
    if (suppressed) continue;
    same_class.push_back(c);
    kept.push_back(c);
    if (max_detections > 0 && int(kept.size()) >= max_detections) break;
  }
  return kept;  // already in (-score, class, anchor) order
}

void ClipBox(Candidate& c, int width, int height) {
  c.x_min = std::clamp(c.x_min, 0.0, double(width));
  c.x_max = std::clamp(c.x_max, 0.0, double(width));
  c.y_min = std::clamp(c.y_min, 0.0, double(height));
  c.y_max = std::clamp(c.y_max, 0.0, double(height));
}

DetectedInstance ToCocoInstance(const Candidate& c, int id) {
  DetectedInstance d;
  d.id = id;
  d.class_id = c.class_id;
  d.class_name = CocoClassName(c.class_id);
  d.confidence = std::clamp(c.score, 0.0, 1.0);
  d.x_min = c.x_min;
  d.y_min = c.y_min;
  d.x_max = c.x_max;
  d.y_max = c.y_max;
  d.has_mask = false;
  return d;
}

}  // namespace dynref::detect
