// ORB-SLAM2 ORBmatcher equivalents (src/ORBmatcher.cc); see matcher.h.
#include "tracking/matcher.h"

#include <cmath>

#include "features/descriptor.h"
#include "features/mnn2.h"
#include "trace/trace_writer.h"

namespace dynref::tracking {
namespace {

using features::kHistoLength;
using features::RowDistance;

// Keeps only matches whose rotation bin is one of the three fullest (ORBmatcher rotHist check).
int ApplyRotationConsistency(const std::vector<std::vector<int>>& hist, Frame& cur) {
  int ind1, ind2, ind3;
  features::ComputeThreeMaxima(hist, &ind1, &ind2, &ind3);
  int removed = 0;
  for (int i = 0; i < kHistoLength; ++i) {
    if (i == ind1 || i == ind2 || i == ind3) continue;
    for (int idx : hist[i]) {
      if (cur.map_point_ids[idx] >= 0) {
        cur.map_point_ids[idx] = -1;
        ++removed;
      }
    }
  }
  return removed;
}

float RadiusByViewingCos(float view_cos) { return view_cos > 0.998f ? 2.5f : 4.0f; }

}  // namespace

bool IsInFrustum(const Frame& f, const MapPoint& p, ProjectedPoint* out) {
  const Camera& cam = *f.camera;
  const Eigen::Vector3d X_c = f.T_cw * p.X_w;
  if (X_c.z() < 0.0) return false;
  const Eigen::Vector2d uv = ProjectPinhole(cam, X_c);
  if (uv.x() < f.min_x || uv.x() > f.max_x || uv.y() < f.min_y || uv.y() > f.max_y) return false;
  const Eigen::Vector3d PO = p.X_w - f.CameraCentre();
  const double dist = PO.norm();
  // Scale invariance region (MapPoint::GetMinDistanceInvariance 0.8 / GetMaxDistanceInvariance 1.2).
  if (dist < 0.8 * p.min_distance || dist > 1.2 * p.max_distance) return false;
  const double view_cos = PO.dot(p.normal) / dist;
  if (view_cos < 0.5) return false;
  out->mp_id = p.id;
  out->u = static_cast<float>(uv.x());
  out->v = static_cast<float>(uv.y());
  out->u_right = static_cast<float>(uv.x() - cam.bf / X_c.z());
  out->predicted_level = p.PredictScale(static_cast<float>(dist), f.pyramid);
  out->view_cos = static_cast<float>(view_cos);
  return true;
}

int SearchByProjectionLastFrame(Frame& cur, const Frame& last, const Map& map, float th) {
  const Camera& cam = *cur.camera;
  std::vector<std::vector<int>> hist(kHistoLength);
  const SE3 T_lc = last.T_cw * cur.T_cw.inverse();
  const double tlc_z = T_lc.translation().z();
  const double b = cam.baseline_m();
  const bool forward = tlc_z > b;
  const bool backward = -tlc_z > b;
  const bool oriented = cur.match_profile.oriented;
  int n = 0;
  for (size_t i = 0; i < last.N(); ++i) {
    const int64_t id = last.map_point_ids[i];
    if (id < 0 || last.outlier[i]) continue;
    const MapPoint* p = map.good_mp(id);
    if (p == nullptr) continue;
    const Eigen::Vector3d X_c = cur.T_cw * p->X_w;
    const double invz = 1.0 / X_c.z();
    if (invz < 0) continue;
    const Eigen::Vector2d uv = ProjectPinhole(cam, X_c);
    if (uv.x() < cur.min_x || uv.x() > cur.max_x || uv.y() < cur.min_y || uv.y() > cur.max_y) continue;
    const int last_octave = last.keys_un[i].octave;
    const float radius = th * cur.pyramid.scale[last_octave];
    std::vector<int> idx;
    const float u = static_cast<float>(uv.x()), v = static_cast<float>(uv.y());
    if (forward) idx = cur.FeaturesInArea(u, v, radius, last_octave);
    else if (backward) idx = cur.FeaturesInArea(u, v, radius, 0, last_octave);
    else idx = cur.FeaturesInArea(u, v, radius, last_octave - 1, last_octave + 1);
    if (idx.empty()) continue;
    float best_dist = cur.match_profile.worst;
    int best_idx = -1;
    for (int i2 : idx) {
      if (cur.map_point_ids[i2] >= 0) continue;
      if (cur.u_right[i2] > 0) {
        const double ur = uv.x() - cam.bf * invz;
        if (std::fabs(ur - cur.u_right[i2]) > radius) continue;
      }
      const float dist = RowDistance(p->descriptor, 0, cur.descriptors, i2);
      if (dist < best_dist) {
        best_dist = dist;
        best_idx = i2;
      }
    }
    if (best_dist <= cur.match_profile.th_high) {
      cur.map_point_ids[best_idx] = id;
      ++n;
      if (oriented) hist[features::RotationBin(last.keys_un[i].angle, cur.keys_un[best_idx].angle)].push_back(best_idx);
    }
  }
  if (oriented) n -= ApplyRotationConsistency(hist, cur);
  return n;
}

int SearchByProjectionLocal(Frame& cur, const std::vector<ProjectedPoint>& points, const Map& map,
                            float th, float nn_ratio) {
  int n = 0;
  for (const ProjectedPoint& pp : points) {
    const MapPoint* p = map.good_mp(pp.mp_id);
    if (p == nullptr) continue;
    const int level = pp.predicted_level;
    float r = RadiusByViewingCos(pp.view_cos);
    r *= th;
    const float radius = r * cur.pyramid.scale[level];
    const std::vector<int> idx = cur.FeaturesInArea(pp.u, pp.v, radius, level - 1, level);
    if (idx.empty()) continue;
    const float worst = cur.match_profile.worst;
    float best_dist = worst, best_dist2 = worst;
    int best_level = -1, best_level2 = -1, best_idx = -1;
    for (int i2 : idx) {
      if (cur.map_point_ids[i2] >= 0) {
        const MapPoint* q = map.good_mp(cur.map_point_ids[i2]);
        if (q != nullptr && q->n_obs > 0) continue;
      }
      if (cur.u_right[i2] > 0 && std::fabs(pp.u_right - cur.u_right[i2]) > radius) continue;
      const float dist = RowDistance(p->descriptor, 0, cur.descriptors, i2);
      if (dist < best_dist) {
        best_dist2 = best_dist;
        best_level2 = best_level;
        best_dist = dist;
        best_level = cur.keys_un[i2].octave;
        best_idx = i2;
      } else if (dist < best_dist2) {
        best_level2 = cur.keys_un[i2].octave;
        best_dist2 = dist;
      }
    }
    if (best_dist <= cur.match_profile.th_high) {
      if (best_level == best_level2 && best_dist > nn_ratio * best_dist2) continue;
      cur.map_point_ids[best_idx] = pp.mp_id;
      ++n;
    }
  }
  return n;
}

std::vector<trace::NamedValue> Mnn2TraceInputs(const features::DescriptorMatch& m, double tau,
                                               std::vector<trace::NamedValue> ids) {
  ids.push_back({"distance", m.distance});
  ids.push_back({"second", m.second});
  ids.push_back({"ratio", m.second > 0 ? m.distance / m.second : 0.0});
  ids.push_back({"tau", tau});
  return ids;
}

namespace {

// MNN2 over the keyframe's map-point features (rows) and the frame's free features (columns).
// At trace level full every row the rule looked at is traced under `stage` (match.mnn2.reference
// or match.mnn2.relocalisation) on its nearest frame feature: the nearest and second-nearest
// distances, the mutual check's reverse nearest and the outcome (accepted, or the first test that
// rejected it: tau, ratio, not mutual, rotation check; ref/trace/README.md).
int SearchByMnn2(const KeyFrame& kf, Frame& cur, const Map& map, double ratio, bool check_orientation,
                 const std::string& stage) {
  const Frame& kff = kf.frame;
  std::vector<int> rows, cols;
  for (size_t i = 0; i < kf.map_point_ids.size(); ++i)
    if (kf.map_point_ids[i] >= 0 && map.good_mp(kf.map_point_ids[i]) != nullptr) rows.push_back(static_cast<int>(i));
  for (size_t j = 0; j < cur.N(); ++j)
    if (cur.map_point_ids[j] < 0 && !cur.IsExcluded(static_cast<int>(j))) cols.push_back(static_cast<int>(j));
  const cv::Mat d = features::DistanceMatrix(kff.descriptors, rows, cur.descriptors, cols);
  features::Mnn2Options o;
  o.ratio = ratio;
  const double tau = cur.match_profile.th_high;
  std::vector<std::vector<int>> hist(kHistoLength);
  const bool orient = check_orientation && cur.match_profile.oriented;
  int n = 0;
  const std::vector<features::Mnn2Candidate> candidates = features::SelectMnn2Candidates(d, tau, o);
  for (const features::Mnn2Candidate& c : candidates) {
    if (c.outcome != features::Mnn2Outcome::kAccepted) continue;
    const int i = rows[static_cast<size_t>(c.match.i)], j = cols[static_cast<size_t>(c.match.j)];
    cur.map_point_ids[j] = kf.map_point_ids[i];
    ++n;
    if (orient) hist[features::RotationBin(kff.keys_un[i].angle, cur.keys_un[j].angle)].push_back(j);
  }
  if (orient) n -= ApplyRotationConsistency(hist, cur);
  if (cur.trace == nullptr || !cur.trace->full_enabled()) return n;
  for (const features::Mnn2Candidate& c : candidates) {
    const int i = rows[static_cast<size_t>(c.match.i)], j = cols[static_cast<size_t>(c.match.j)];
    double outcome = static_cast<double>(c.outcome);
    if (c.outcome == features::Mnn2Outcome::kAccepted && cur.map_point_ids[j] != kf.map_point_ids[i])
      outcome = kMnn2OutcomeRotation;  // dropped by the rotation check
    std::vector<trace::NamedValue> in =
        Mnn2TraceInputs(c.match, tau, {{"kf", double(kf.id)}, {"kf_feature", double(i)},
                                       {"map_point", double(kf.map_point_ids[i])}});
    in.push_back({"rho", ratio});
    in.push_back({"second_feature", c.second_j < 0 ? -1.0 : double(cols[static_cast<size_t>(c.second_j)])});
    in.push_back({"reverse_kf_feature", double(rows[static_cast<size_t>(c.reverse_i)])});
    in.push_back({"reverse_distance", c.reverse_distance});
    in.push_back({"rotation_check", orient ? 1.0 : 0.0});
    in.push_back({"kf_angle", orient ? double(kff.keys_un[i].angle) : 0.0});
    in.push_back({"angle", orient ? double(cur.keys_un[j].angle) : 0.0});
    in.push_back({"outcome", outcome});
    cur.trace->ProbabilityUpdate(stage, trace::EntityKind::kFeature, cur.FeatureId(j), in, 0.0, 0.0);
  }
  return n;
}

}  // namespace

int SearchByBruteForce(const KeyFrame& kf, Frame& cur, const Map& map, float nn_ratio, bool check_orientation,
                       const features::BackboneMnn2& mnn2, const std::string& mnn2_stage) {
  if (mnn2.enabled) return SearchByMnn2(kf, cur, map, mnn2.ratio, check_orientation, mnn2_stage);
  std::vector<std::vector<int>> hist(kHistoLength);
  const Frame& kff = kf.frame;
  const bool orient = check_orientation && cur.match_profile.oriented;
  const float worst = cur.match_profile.worst;
  int n = 0;
  for (size_t i = 0; i < kf.map_point_ids.size(); ++i) {
    const int64_t id = kf.map_point_ids[i];
    if (id < 0 || map.good_mp(id) == nullptr) continue;
    float best1 = worst, best2 = worst;
    int best_idx = -1;
    for (size_t j = 0; j < cur.N(); ++j) {
      if (cur.map_point_ids[j] >= 0 || cur.IsExcluded(static_cast<int>(j))) continue;
      const float dist = RowDistance(kff.descriptors, static_cast<int>(i), cur.descriptors, static_cast<int>(j));
      if (dist < best1) {
        best2 = best1;
        best1 = dist;
        best_idx = static_cast<int>(j);
      } else if (dist < best2) {
        best2 = dist;
      }
    }
    if (best1 <= cur.match_profile.th_low && best1 < nn_ratio * best2) {
      cur.map_point_ids[best_idx] = id;
      ++n;
      if (orient) hist[features::RotationBin(kff.keys_un[i].angle, cur.keys_un[best_idx].angle)].push_back(best_idx);
    }
  }
  if (orient) n -= ApplyRotationConsistency(hist, cur);
  return n;
}

int SearchByProjectionKeyFrame(Frame& cur, const KeyFrame& kf, const Map& map,
                               const std::set<int64_t>& already_found, float th, float max_dist) {
  const Camera& cam = *cur.camera;
  const bool oriented = cur.match_profile.oriented;
  std::vector<std::vector<int>> hist(kHistoLength);
  const Eigen::Vector3d O_w = cur.CameraCentre();
  int n = 0;
  for (size_t i = 0; i < kf.map_point_ids.size(); ++i) {
    const int64_t id = kf.map_point_ids[i];
    const MapPoint* p = id >= 0 ? map.good_mp(id) : nullptr;
    if (p == nullptr || already_found.count(id)) continue;
    const Eigen::Vector3d X_c = cur.T_cw * p->X_w;
    if (X_c.z() <= 0) continue;
    const Eigen::Vector2d uv = ProjectPinhole(cam, X_c);
    if (uv.x() < cur.min_x || uv.x() > cur.max_x || uv.y() < cur.min_y || uv.y() > cur.max_y) continue;
    const double dist3 = (p->X_w - O_w).norm();
    if (dist3 < 0.8 * p->min_distance || dist3 > 1.2 * p->max_distance) continue;
    const int level = p->PredictScale(static_cast<float>(dist3), cur.pyramid);
    const float radius = th * cur.pyramid.scale[level];
    const std::vector<int> idx = cur.FeaturesInArea(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                                                    radius, level - 1, level + 1);
    float best_dist = cur.match_profile.worst;
    int best_idx = -1;
    for (int i2 : idx) {
      if (cur.map_point_ids[i2] >= 0) continue;
      const float dist = RowDistance(p->descriptor, 0, cur.descriptors, i2);
      if (dist < best_dist) {
        best_dist = dist;
        best_idx = i2;
      }
    }
    if (best_idx >= 0 && best_dist <= max_dist) {
      cur.map_point_ids[best_idx] = id;
      ++n;
      if (oriented) hist[features::RotationBin(kf.frame.keys_un[i].angle, cur.keys_un[best_idx].angle)].push_back(best_idx);
    }
  }
  if (oriented) n -= ApplyRotationConsistency(hist, cur);
  return n;
}

}  // namespace dynref::tracking
