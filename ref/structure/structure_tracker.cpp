#include "structure/structure_tracker.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <tuple>

#include "core/cpu_clock.h"
#include "features/orb_extractor.h"

namespace dynref::structure {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Nearest valid depth in the 5 x 5 window around (u, v); 0 when none.
float NearestDepth(const cv::Mat& depth_m, double u, double v) {
  const int cu = static_cast<int>(std::lround(u)), cv_ = static_cast<int>(std::lround(v));
  float best = 0;
  for (int y = cv_ - 2; y <= cv_ + 2; ++y)
    for (int x = cu - 2; x <= cu + 2; ++x) {
      if (x < 0 || y < 0 || x >= depth_m.cols || y >= depth_m.rows) continue;
      const float z = depth_m.at<float>(y, x);
      if (z > 0 && std::isfinite(z) && (best == 0 || z < best)) best = z;
    }
  return best;
}

}  // namespace

StructureTracker::StructureTracker(const Camera& camera, const StructureOptions& options, trace::TraceWriter& trace)
    : camera_(camera), o_(options), trace_(trace) {
  o_.Check();
}

void StructureTracker::Extract(Frame& f, double* lines_ms, double* planes_ms) const {
  FrameStructure& s = f.structure;
  s = FrameStructure{};
  s.enabled = true;
  const Intrinsics K = camera_.Pinhole();
  const double t0 = ThreadCpuMs();
  if (o_.lines) {
    const features::SegmentSet set = features::DetectSegments(f.grey, o_.line);
    std::vector<cv::Point2f> raw, un;
    for (const features::Segment& g : set.segments) {
      raw.emplace_back(static_cast<float>(g.s.x()), static_cast<float>(g.s.y()));
      raw.emplace_back(static_cast<float>((g.s.x() + g.e.x()) / 2), static_cast<float>((g.s.y() + g.e.y()) / 2));
      raw.emplace_back(static_cast<float>(g.e.x()), static_cast<float>(g.e.y()));
    }
    un = raw;
    if (camera_.HasDistortion() && !raw.empty()) {
      cv::Mat Km(camera_.K());
      cv::undistortPoints(raw, un, Km, camera_.DistCoeffs(), cv::noArray(), Km);
    }
    for (size_t i = 0; i < set.segments.size(); ++i) {
      const features::Segment& g = set.segments[i];
      FrameLine L;
      L.s = {un[3 * i].x, un[3 * i].y};
      L.e = {un[3 * i + 2].x, un[3 * i + 2].y};
      L.l = features::LineThrough(L.s, L.e);
      // Endpoints merged by undistortion: no line (l = 0); kept for index alignment, never associated.
      L.angle = g.angle;
      L.length = (L.e - L.s).norm();
      L.group = g.group;
      L.companion = g.companion;
      int with_depth = 0;
      for (size_t k = 0; k < 3; ++k) {
        const float z = f.depth_m.empty() ? 0.f : NearestDepth(f.depth_m, raw[3 * i + k].x, raw[3 * i + k].y);
        L.sample_depth[k] = z > 0 ? 1 : 0;
        if (z > 0) L.X_c[k] = K.Backproject(un[3 * i + k].x, un[3 * i + k].y, z), ++with_depth;
      }
      if (with_depth == 3) {
        const Eigen::Vector3d a = L.X_c[0], b = L.X_c[2], m = L.X_c[1];
        const double len = (b - a).norm();
        if (len >= o_.line_min_3d_length_m) {
          const Eigen::Vector3d dir = (b - a) / len;
          const double off = ((m - a) - (m - a).dot(dir) * dir).norm();
          L.has_3d = off <= o_.line_collinear_m + 0.01 * m.z();
        }
      }
      s.lines.push_back(L);
    }
    s.line_descriptors = set.descriptors;
  }
  const double t1 = ThreadCpuMs();
  if (lines_ms != nullptr) *lines_ms += t1 - t0;
  if (o_.planes && !f.depth_m.empty()) {
    features::PlaneSegmentation seg = features::SegmentPlanes(f.depth_m, K, o_.plane);
    s.planes = std::move(seg.planes);
    s.plane_labels = seg.labels;
  }
  if (planes_ms != nullptr) *planes_ms += ThreadCpuMs() - t1;
  s.Reset(s.lines.size(), s.planes.size());
  trace_.FrameCount("structure.extract", "lines", static_cast<int64_t>(s.lines.size()));
  int with3d = 0;
  for (const FrameLine& L : s.lines) with3d += L.has_3d;
  trace_.FrameCount("structure.extract", "lines_3d", with3d);
  trace_.FrameCount("structure.extract", "planes", static_cast<int64_t>(s.planes.size()));
}

double StructureTracker::Associate(Frame& f, const Map& map) const {
  FrameStructure& s = f.structure;
  if (!s.enabled) return 0;
  std::fill(s.map_line_ids.begin(), s.map_line_ids.end(), -1);
  std::fill(s.line_outlier.begin(), s.line_outlier.end(), 0);
  std::fill(s.map_plane_ids.begin(), s.map_plane_ids.end(), -1);
  std::fill(s.plane_outlier.begin(), s.plane_outlier.end(), 0);
  const Intrinsics K = camera_.Pinhole();
  int n_lines = 0, n_planes = 0;
  if (!s.lines.empty()) {
    // Candidates: (score, map id, frame index); score = mean midpoint distance in px.
    std::vector<std::tuple<double, int64_t, int>> cand;
    const double gate = o_.line_match_angle_deg * kDeg;
    for (const auto& [id, L] : map.lines) {
      if (L->bad) continue;
      const Eigen::Vector3d a = f.T_cw * L->P_s, b = f.T_cw * L->P_e;
      if (a.z() < 0.1 || b.z() < 0.1) continue;
      const Eigen::Vector2d pa = K.Project(a), pb = K.Project(b);
      const Eigen::Vector2d mid = 0.5 * (pa + pb);
      if (!f.InImage(static_cast<float>(mid.x()), static_cast<float>(mid.y())) &&
          !f.InImage(static_cast<float>(pa.x()), static_cast<float>(pa.y())) &&
          !f.InImage(static_cast<float>(pb.x()), static_cast<float>(pb.y())))
        continue;
      const Eigen::Vector3d lp = features::LineThrough(pa, pb);
      if (lp.head<2>().squaredNorm() == 0) continue;
      double ang = std::atan2(pb.y() - pa.y(), pb.x() - pa.x());
      if (ang < 0) ang += M_PI;
      if (ang >= M_PI) ang -= M_PI;
      const Eigen::Vector2d dir = (pb - pa).normalized();
      const double t0 = 0, t1 = (pb - pa).norm();
      for (size_t i = 0; i < s.lines.size(); ++i) {
        const FrameLine& F = s.lines[i];
        if (s.line_weight[i] <= 0) continue;  // taken out by a dynamic stage (FrameEdit::SetLineWeight)
        if (F.l.head<2>().squaredNorm() == 0 || features::LineAngleDiff(ang, F.angle) >= gate) continue;
        const Eigen::Vector2d fm = 0.5 * (F.s + F.e);
        const double d1 = std::fabs(lp.dot(Eigen::Vector3d(fm.x(), fm.y(), 1)));
        const double d2 = std::fabs(F.l.dot(Eigen::Vector3d(mid.x(), mid.y(), 1)));
        if (d1 > o_.line_match_px || d2 > o_.line_match_px) continue;
        // The observed segment must overlap the projected one along the line.
        const double u0 = (F.s - pa).dot(dir), u1 = (F.e - pa).dot(dir);
        if (std::max(u0, u1) < t0 || std::min(u0, u1) > t1) continue;
        if (features::DescriptorDistance(L->descriptor, s.line_descriptors.row(static_cast<int>(i))) > o_.line_match_bits)
          continue;
        cand.emplace_back(0.5 * (d1 + d2), id, static_cast<int>(i));
      }
    }
    std::stable_sort(cand.begin(), cand.end());
    std::set<int64_t> used;
    for (const auto& [score, id, i] : cand) {
      (void)score;
      if (s.map_line_ids[static_cast<size_t>(i)] >= 0 || used.count(id)) continue;
      s.map_line_ids[static_cast<size_t>(i)] = id;
      used.insert(id);
      ++n_lines;
    }
  }
  if (!s.planes.empty()) {
    std::vector<std::tuple<double, int64_t, int>> cand;
    const double cos_gate = std::cos(o_.plane_match_angle_deg * kDeg);
    for (const auto& [id, P] : map.planes) {
      if (P->bad) continue;
      const Eigen::Vector3d n_c = f.T_cw.linear() * P->n;
      const double d_c = P->d - n_c.dot(f.T_cw.translation());
      for (size_t j = 0; j < s.planes.size(); ++j) {
        const double c = n_c.dot(s.planes[j].n);
        const double dd = std::fabs(d_c - s.planes[j].d);
        if (c < cos_gate || dd > o_.plane_match_dist_m) continue;
        const double angle = std::acos(std::min(1.0, c));
        cand.emplace_back(angle / (o_.plane_match_angle_deg * kDeg) + dd / o_.plane_match_dist_m, id, static_cast<int>(j));
      }
    }
    std::stable_sort(cand.begin(), cand.end());
    std::set<int64_t> used;
    for (const auto& [score, id, j] : cand) {
      (void)score;
      if (s.map_plane_ids[static_cast<size_t>(j)] >= 0 || used.count(id)) continue;
      s.map_plane_ids[static_cast<size_t>(j)] = id;
      used.insert(id);
      ++n_planes;
    }
  }
  return o_.line_count_weight * n_lines + o_.plane_count_weight * n_planes;
}

optim::PoseStructure StructureTracker::BuildPoseStructure(const Frame& f, const Map& map, std::vector<int>* line_index,
                                                          std::vector<int>* plane_index) const {
  optim::PoseStructure ps;
  ps.options = o_.residual;
  line_index->clear();
  plane_index->clear();
  const FrameStructure& s = f.structure;
  const bool ids = trace_.full_enabled();
  for (size_t i = 0; i < s.lines.size(); ++i) {
    const MapLine* L = s.map_line_ids[i] >= 0 ? map.good_line(s.map_line_ids[i]) : nullptr;
    if (L == nullptr || s.line_weight[i] <= 0) continue;
    optim::LineObservation o;
    o.X_w = L->Samples();
    o.l = s.lines[i].l;
    o.weight = s.line_weight[i];
    if (o_.line_parallel_term && s.lines[i].companion >= 0 &&
        s.lines[static_cast<size_t>(s.lines[i].companion)].l.head<2>().squaredNorm() > 0) {
      o.l_companion = s.lines[static_cast<size_t>(s.lines[i].companion)].l;
      o.has_companion = true;
    }
    if (ids) o.obs_id = L->TraceId() + "@f" + std::to_string(f.index), o.trace_line = static_cast<int64_t>(i);
    ps.lines.push_back(o);
    line_index->push_back(static_cast<int>(i));
  }
  for (size_t j = 0; j < s.planes.size(); ++j) {
    const MapPlane* P = s.map_plane_ids[j] >= 0 ? map.good_plane(s.map_plane_ids[j]) : nullptr;
    if (P == nullptr) continue;
    optim::PlaneObservationResidual o;
    o.n_w = P->n, o.d_w = P->d;
    o.n_obs = s.planes[j].n, o.d_obs = s.planes[j].d;
    if (ids) o.obs_id = P->TraceId() + "@f" + std::to_string(f.index), o.trace_plane = static_cast<int64_t>(j);
    ps.planes.push_back(o);
    plane_index->push_back(static_cast<int>(j));
  }
  return ps;
}

void StructureTracker::ApplyPoseResult(Frame& f, const optim::PoseOnlyResult& r, const std::vector<int>& line_index,
                                       const std::vector<int>& plane_index) const {
  FrameStructure& s = f.structure;
  for (size_t k = 0; k < line_index.size(); ++k) s.line_outlier[static_cast<size_t>(line_index[k])] = r.line_inlier[k] ? 0 : 1;
  for (size_t k = 0; k < plane_index.size(); ++k)
    s.plane_outlier[static_cast<size_t>(plane_index[k])] = r.plane_inlier[k] ? 0 : 1;
}

double StructureTracker::InlierCount(const Frame& f) const {
  const FrameStructure& s = f.structure;
  int nl = 0, np = 0;
  for (size_t i = 0; i < s.map_line_ids.size(); ++i) nl += s.map_line_ids[i] >= 0 && !s.line_outlier[i];
  for (size_t j = 0; j < s.map_plane_ids.size(); ++j) np += s.map_plane_ids[j] >= 0 && !s.plane_outlier[j];
  return o_.line_count_weight * nl + o_.plane_count_weight * np;
}

void StructureTracker::DiscardOutliers(Frame& f) const {
  FrameStructure& s = f.structure;
  for (size_t i = 0; i < s.map_line_ids.size(); ++i)
    if (s.line_outlier[i]) s.map_line_ids[i] = -1, s.line_outlier[i] = 0;
  for (size_t j = 0; j < s.map_plane_ids.size(); ++j)
    if (s.plane_outlier[j]) s.map_plane_ids[j] = -1, s.plane_outlier[j] = 0;
}

void StructureTracker::CreateLandmarks(Frame& f, KeyFrame& kf, Map& map) const {
  FrameStructure& s = f.structure;
  FrameStructure& ks = kf.frame.structure;
  ks.plane_labels.release();  // per-frame overlay data, not kept in the map
  std::fill(ks.map_line_ids.begin(), ks.map_line_ids.end(), -1);
  std::fill(ks.map_plane_ids.begin(), ks.map_plane_ids.end(), -1);
  const SE3 T_wc = f.T_cw.inverse();
  int new_lines = 0, new_planes = 0;
  for (size_t i = 0; i < s.lines.size(); ++i) {
    if (s.line_weight[i] <= 0) continue;  // dynamic: neither observes nor creates a map line
    const int64_t id = s.line_outlier[i] ? -1 : s.map_line_ids[i];
    if (id >= 0 && map.good_line(id) != nullptr) {
      map.AddLineObservation(id, kf.id, static_cast<int>(i));
    } else if (s.lines[i].has_3d) {
      MapLine* L = map.NewMapLine(T_wc * s.lines[i].X_c[0], T_wc * s.lines[i].X_c[2],
                                  s.line_descriptors.row(static_cast<int>(i)), kf.id, f.index);
      map.AddLineObservation(L->id, kf.id, static_cast<int>(i));
      s.map_line_ids[i] = L->id;
      ++new_lines;
    }
  }
  for (size_t j = 0; j < s.planes.size(); ++j) {
    const int64_t id = s.plane_outlier[j] ? -1 : s.map_plane_ids[j];
    if (id >= 0 && map.good_plane(id) != nullptr) {
      map.AddPlaneObservation(id, kf.id, static_cast<int>(j));
    } else {
      // Camera plane n_c^T X_c + d_c = 0 with X_c = R X_w + t: n_w = R^T n_c, d_w = d_c + n_c^T t.
      const Eigen::Vector3d n_w = f.T_cw.linear().transpose() * s.planes[j].n;
      const double d_w = s.planes[j].d + s.planes[j].n.dot(f.T_cw.translation());
      MapPlane* P = map.NewMapPlane(n_w, d_w, kf.id, f.index);
      map.AddPlaneObservation(P->id, kf.id, static_cast<int>(j));
      s.map_plane_ids[j] = P->id;
      ++new_planes;
    }
  }
  trace_.FrameCount("structure.keyframe", "new_lines", new_lines);
  trace_.FrameCount("structure.keyframe", "new_planes", new_planes);
}

void StructureTracker::FillLocalBA(const Map& map, const std::set<int64_t>& local, std::set<int64_t>* fixed,
                                   optim::LocalBAStructure* st) const {
  st->options = o_.residual;
  std::set<int64_t> lines, planes;
  for (int64_t k_id : local) {
    const FrameStructure& s = map.kf(k_id)->frame.structure;
    for (int64_t id : s.map_line_ids)
      if (id >= 0 && map.good_line(id) != nullptr) lines.insert(id);
    for (int64_t id : s.map_plane_ids)
      if (id >= 0 && map.good_plane(id) != nullptr) planes.insert(id);
  }
  const auto usable = [&](int64_t k_id) {
    const KeyFrame* k = map.kf(k_id);
    if (k == nullptr || k->bad) return false;
    if (!local.count(k_id)) fixed->insert(k_id);
    return true;
  };
  for (int64_t id : lines) {
    const MapLine* L = map.good_line(id);
    st->lines.push_back({id, L->P_s, L->P_e});
    for (const auto& [k_id, idx] : L->observations) {
      if (!usable(k_id)) continue;
      const FrameStructure& s = map.kf(k_id)->frame.structure;
      const FrameLine& F = s.lines[static_cast<size_t>(idx)];
      optim::BALineObservation o;
      o.kf_id = k_id, o.line_id = id, o.l = F.l, o.weight = s.line_weight[static_cast<size_t>(idx)], o.trace_line = idx;
      if (o_.line_parallel_term && F.companion >= 0 && s.lines[static_cast<size_t>(F.companion)].l.head<2>().squaredNorm() > 0)
        o.l_companion = s.lines[static_cast<size_t>(F.companion)].l, o.has_companion = true;
      st->line_observations.push_back(o);
    }
  }
  for (int64_t id : planes) {
    const MapPlane* P = map.good_plane(id);
    st->planes.push_back({id, P->n, P->d});
    for (const auto& [k_id, idx] : P->observations) {
      if (!usable(k_id)) continue;
      const features::PlaneObservation& F = map.kf(k_id)->frame.structure.planes[static_cast<size_t>(idx)];
      optim::BAPlaneObservation o;
      o.kf_id = k_id, o.plane_id = id, o.n_obs = F.n, o.d_obs = F.d, o.trace_plane = idx;
      st->plane_observations.push_back(o);
    }
  }
}

int StructureTracker::ApplyLocalBA(Map& map, const optim::LocalBAStructure& st, const optim::LocalBAResult& r) const {
  int outliers = 0;
  for (size_t i = 0; i < st.line_observations.size(); ++i) {
    if (r.line_inlier[i]) continue;
    const optim::BALineObservation& o = st.line_observations[i];
    MapLine* L = map.good_line(o.line_id);
    KeyFrame* k = map.kf(o.kf_id);
    if (L == nullptr || k == nullptr) continue;
    auto it = L->observations.find(o.kf_id);
    if (it != L->observations.end()) {
      k->frame.structure.map_line_ids[static_cast<size_t>(it->second)] = -1;
      L->observations.erase(it);
    }
    if (L->observations.empty()) map.SetBadLine(o.line_id);
    ++outliers;
  }
  for (size_t i = 0; i < st.plane_observations.size(); ++i) {
    if (r.plane_inlier[i]) continue;
    const optim::BAPlaneObservation& o = st.plane_observations[i];
    MapPlane* P = map.good_plane(o.plane_id);
    KeyFrame* k = map.kf(o.kf_id);
    if (P == nullptr || k == nullptr) continue;
    auto it = P->observations.find(o.kf_id);
    if (it != P->observations.end()) {
      k->frame.structure.map_plane_ids[static_cast<size_t>(it->second)] = -1;
      P->observations.erase(it);
    }
    ++outliers;
  }
  ApplyLandmarks(map, r);
  return outliers;
}

void StructureTracker::ApplyLandmarks(Map& map, const optim::LocalBAResult& r) const {
  for (const auto& [id, P] : r.line_P) {
    MapLine* L = map.good_line(id);
    if (L != nullptr) L->P_s = P.first, L->P_e = P.second;
  }
  for (const auto& [id, p] : r.plane) {
    MapPlane* P = map.good_plane(id);
    if (P != nullptr) P->n = p.first.normalized(), P->d = p.second;
  }
}

void StructureTracker::TraceFrame(const Frame& f) const {
  if (!trace_.full_enabled()) return;
  const FrameStructure& s = f.structure;
  for (size_t i = 0; i < s.lines.size(); ++i) {
    const FrameLine& L = s.lines[i];
    const int64_t id = s.line_outlier.empty() || s.line_outlier[i] ? -1 : s.map_line_ids[i];
    trace_.ProbabilityUpdate(trace::kGeometryStage, trace::EntityKind::kLineSample, FrameStructure::LineId(f.index, static_cast<int>(i)),
                             {{"x0", L.s.x()}, {"y0", L.s.y()}, {"x1", L.e.x()}, {"y1", L.e.y()},
                              {"map_line", static_cast<double>(id)}, {"has_3d", L.has_3d ? 1.0 : 0.0},
                              {"group", static_cast<double>(L.group)}},
                             0.0, 0.0);
  }
  // Plane bounding boxes from the label image, one pass.
  std::vector<std::array<int, 4>> box(s.planes.size(), {1 << 30, 1 << 30, -1, -1});
  for (int r = 0; r < s.plane_labels.rows; ++r)
    for (int c = 0; c < s.plane_labels.cols; ++c) {
      const int l = s.plane_labels.at<int16_t>(r, c);
      if (l < 0) continue;
      auto& b = box[static_cast<size_t>(l)];
      b[0] = std::min(b[0], c), b[1] = std::min(b[1], r), b[2] = std::max(b[2], c), b[3] = std::max(b[3], r);
    }
  for (size_t j = 0; j < s.planes.size(); ++j) {
    const features::PlaneObservation& P = s.planes[j];
    const int64_t id = s.plane_outlier.empty() || s.plane_outlier[j] ? -1 : s.map_plane_ids[j];
    trace_.ProbabilityUpdate(trace::kGeometryStage, trace::EntityKind::kPlane, FrameStructure::PlaneId(f.index, static_cast<int>(j)),
                             {{"x_min", static_cast<double>(box[j][0])}, {"y_min", static_cast<double>(box[j][1])},
                              {"x_max", static_cast<double>(box[j][2])}, {"y_max", static_cast<double>(box[j][3])},
                              {"n_x", P.n.x()}, {"n_y", P.n.y()}, {"n_z", P.n.z()}, {"d", P.d},
                              {"points", static_cast<double>(P.points)}, {"map_plane", static_cast<double>(id)}},
                             0.0, 0.0);
  }
}

void StructureTracker::MaintainMap(Map& map, int64_t kf_id, const std::set<int64_t>& local) const {
  int culled = 0, merged = 0;
  std::vector<int64_t> to_cull;
  for (const auto& [id, L] : map.lines)
    if (!L->bad && L->first_kf <= kf_id - 3 && L->observations.size() < 2) to_cull.push_back(id);
  for (int64_t id : to_cull) map.SetBadLine(id), ++culled;
  // Plane merging among the planes the local keyframes observe (ascending ids: older survive).
  std::set<int64_t> planes;
  for (int64_t k_id : local) {
    const KeyFrame* k = map.kf(k_id);
    if (k == nullptr || k->bad) continue;
    for (int64_t id : k->frame.structure.map_plane_ids)
      if (id >= 0 && map.good_plane(id) != nullptr) planes.insert(id);
  }
  const double cos_merge = std::cos(o_.plane_merge_angle_deg * kDeg);
  const std::vector<int64_t> ids(planes.begin(), planes.end());
  for (size_t a = 0; a < ids.size(); ++a) {
    const MapPlane* A = map.good_plane(ids[a]);
    if (A == nullptr) continue;
    for (size_t b = a + 1; b < ids.size(); ++b) {
      const MapPlane* B = map.good_plane(ids[b]);
      if (B == nullptr) continue;
      if (A->n.dot(B->n) >= cos_merge && std::fabs(A->d - B->d) <= o_.plane_merge_dist_m) {
        map.ReplacePlane(ids[b], ids[a]);
        ++merged;
      }
    }
  }
  trace_.FrameCount("structure.map", "culled_lines", culled);
  trace_.FrameCount("structure.map", "merged_planes", merged);
  trace_.FrameCount("structure.map", "lines", static_cast<int64_t>(map.GoodLineCount()));
  trace_.FrameCount("structure.map", "planes", static_cast<int64_t>(map.GoodPlaneCount()));
}

}  // namespace dynref::structure
