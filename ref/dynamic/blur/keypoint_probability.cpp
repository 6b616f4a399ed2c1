#include "dynamic/blur/keypoint_probability.h"

#include <cmath>
#include <stdexcept>

#include "geometry/point_index_2d.h"

namespace dynref::blur {

void KeypointProbabilityOptions::Check() const {
  if (!(radius_px > 0)) throw std::invalid_argument("radius_px must be > 0");
  if (!(c1 >= 0)) throw std::invalid_argument("c1 must be >= 0");
  if (!(c2 >= 0)) throw std::invalid_argument("c2 must be >= 0");
  if (!(theta >= 0 && theta < 1)) throw std::invalid_argument("theta must be in [0, 1)");
}

std::vector<KeypointProbability> KeypointProbabilities(const std::vector<cv::Point2f>& points,
                                                       const std::vector<uint8_t>& in_mask,
                                                       const KeypointProbabilityOptions& o) {
  if (points.size() != in_mask.size()) throw std::invalid_argument("KeypointProbabilities: size mismatch");
  std::vector<KeypointProbability> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) out[i].pre = out[i].post = in_mask[i] ? 1.0 : 0.0;
  if (o.compute) {
    const geometry::PointIndex2D index(points);
    std::vector<int> nb;
    std::vector<double> dist;
    for (size_t i = 0; i < points.size(); ++i) {
      if (out[i].pre != 0) continue;  // mask keypoints keep P = 1
      index.Within(points[i], o.radius_px, &nb, &dist);
      double sum = 0;
      int n = 0;
      for (size_t k = 0; k < nb.size(); ++k) {
        if (size_t(nb[k]) == i) continue;  // k != i
        ++n;
        if (out[size_t(nb[k])].pre == 0) continue;
        ++out[i].dynamic_neighbours;
        sum += o.c1 * std::exp(-o.c2 * dist[k]);  // lambda(r_k) * P(x_k), P = 1
      }
      out[i].neighbours = n;
      out[i].post = n > 0 ? sum / n : 0.0;
    }
  }
  for (KeypointProbability& k : out) k.dynamic = k.post > o.theta;
  return out;
}

}  // namespace dynref::blur
