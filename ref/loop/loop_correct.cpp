// LoopClosing::CorrectLoop, the essential graph it optimises and the global BA after it
// (loop_closer.h steps 3-5).
#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include "core/cpu_clock.h"
#include "loop/essential_graph.h"
#include "loop/global_ba.h"
#include "loop/loop_closer.h"
#include "loop/loop_matcher.h"

namespace dynref::loop {
namespace {

std::set<int64_t> Neighbours(const KeyFrame& k) {
  std::set<int64_t> s;
  for (const auto& [id, w] : k.connections) s.insert(id);
  return s;
}

// The keyframe and its good covisibles, in id order.
std::vector<int64_t> CorrectConnectedKeyFrames(Map& map, const KeyFrame& kf) {
  std::vector<int64_t> connected{kf.id};
  for (int64_t id : kf.ordered_covisibles)
    if (map.kf(id) != nullptr && !map.kf(id)->bad) connected.push_back(id);
  std::sort(connected.begin(), connected.end());
  return connected;
}

// Moves the connected keyframes to their corrected poses and their map points with them (each
// point once, by the first keyframe in id order that sees it: ORB-SLAM2 mnCorrectedByKF /
// mnCorrectedReference); returns point -> the keyframe whose correction moved it.
std::map<int64_t, int64_t> CorrectKeyFramesAndPoints(Map& map, const std::vector<int64_t>& connected,
                                                     const std::map<int64_t, SE3>& corrected,
                                                     const std::map<int64_t, SE3>& non_corrected) {
  std::map<int64_t, int64_t> corrected_by;
  for (int64_t id : connected) {
    KeyFrame* k = map.kf(id);
    const SE3 move = corrected.at(id).inverse() * non_corrected.at(id);
    for (int64_t mp : k->map_point_ids) {
      MapPoint* p = mp >= 0 ? map.good_mp(mp) : nullptr;
      if (p == nullptr || corrected_by.count(mp)) continue;
      p->X_w = move * p->X_w;
      corrected_by[mp] = id;
      map.UpdatePointNormalAndDepth(mp);
    }
  }
  for (int64_t id : connected) map.kf(id)->T_cw = corrected.at(id);
  for (int64_t id : connected) map.UpdateConnections(id);
  return corrected_by;
}

// Loop fusion: the keyframe's matched features take the loop points.
void CorrectFuseMatched(Map& map, KeyFrame& kf, const std::vector<int64_t>& matched) {
  for (size_t i = 0; i < matched.size(); ++i) {
    const int64_t loop_mp = matched[i];
    if (loop_mp < 0 || map.good_mp(loop_mp) == nullptr) continue;
    const int64_t own = kf.map_point_ids[i];
    if (own >= 0 && map.good_mp(own) != nullptr) {
      if (own != loop_mp) map.ReplacePoint(own, loop_mp);
    } else {
      map.AddObservation(loop_mp, kf.id, static_cast<int>(i));
    }
    if (map.good_mp(loop_mp) != nullptr) map.UpdatePointDescriptor(loop_mp);
  }
}

// SearchAndFuse: the loop points into every corrected keyframe.
void CorrectSearchAndFuse(Map& map, const std::vector<int64_t>& connected, const std::map<int64_t, SE3>& corrected,
                          const std::vector<int64_t>& loop_points) {
  for (int64_t id : connected) {
    KeyFrame* k = map.kf(id);
    if (k == nullptr || k->bad) continue;
    const FuseResult fr = FusePose(*k, corrected.at(id), loop_points, map, 4.0f);
    for (const auto& [own, by] : fr.replace)
      if (map.good_mp(own) != nullptr && map.good_mp(by) != nullptr) map.ReplacePoint(own, by);
    for (const auto& [feature, by] : fr.add)
      if (map.good_mp(by) != nullptr && k->map_point_ids[feature] < 0) map.AddObservation(by, id, feature);
  }
}

// New links made by the fusion (ORB-SLAM2 LoopConnections).
std::map<int64_t, std::set<int64_t>> CorrectLoopConnections(Map& map, const std::vector<int64_t>& connected) {
  std::map<int64_t, std::set<int64_t>> loop_connections;
  const std::set<int64_t> connected_set(connected.begin(), connected.end());
  for (int64_t id : connected) {
    KeyFrame* k = map.kf(id);
    if (k == nullptr || k->bad) continue;
    const std::set<int64_t> previous = Neighbours(*k);
    map.UpdateConnections(id);
    std::set<int64_t>& lc = loop_connections[id];
    for (int64_t n : Neighbours(*k))
      if (!previous.count(n) && !connected_set.count(n)) lc.insert(n);
  }
  return loop_connections;
}

// The essential graph's vertices (good keyframes, current poses) and spanning-tree children.
struct CorrectGraph {
  std::map<int64_t, SE3> T_cw;
  std::map<int64_t, std::set<int64_t>> children;
  std::vector<PoseGraphEdge> edges;
  std::set<std::pair<int64_t, int64_t>> inserted;  // loop-connection edges (unordered pairs)
};

std::pair<int64_t, int64_t> CorrectEdgeKey(int64_t a, int64_t b) { return std::make_pair(std::min(a, b), std::max(a, b)); }

// Loop-connection edges at the corrected poses (weak links only for the loop edge itself).
void CorrectAddLoopConnectionEdges(const Map& map, const std::map<int64_t, std::set<int64_t>>& loop_connections,
                                   int64_t kf_id, int64_t loop_kf, int min_weight, CorrectGraph* g) {
  for (const auto& [i, set] : loop_connections) {
    for (int64_t j : set) {
      if (!g->T_cw.count(i) || !g->T_cw.count(j)) continue;
      const auto w = map.kf(i)->connections.find(j);
      const int weight = w == map.kf(i)->connections.end() ? 0 : w->second;
      if ((i != kf_id || j != loop_kf) && weight < min_weight) continue;
      g->edges.push_back({i, j, SE3(g->T_cw.at(j) * g->T_cw.at(i).inverse())});
      g->inserted.insert(CorrectEdgeKey(i, j));
    }
  }
}

// Spanning-tree, loop and strong covisibility edges at the poses before the correction.
void CorrectAddGraphEdges(const Map& map, const std::map<int64_t, SE3>& non_corrected,
                          const std::map<int64_t, std::set<int64_t>>& loop_edges, int min_weight, CorrectGraph* g) {
  const std::map<int64_t, SE3>& T_cw = g->T_cw;
  auto before = [&](int64_t id) { return non_corrected.count(id) ? non_corrected.at(id) : T_cw.at(id); };
  for (const auto& [i, T_iw] : T_cw) {
    const KeyFrame* k = map.kf(i);
    const SE3 T_wi = before(i).inverse();
    auto add = [&](int64_t j) { g->edges.push_back({i, j, SE3(before(j) * T_wi)}); };
    if (k->parent >= 0 && T_cw.count(k->parent)) add(k->parent);
    const auto le = loop_edges.find(i);
    if (le != loop_edges.end())
      for (int64_t j : le->second)
        if (j < i && T_cw.count(j)) add(j);
    for (int64_t j : k->CovisiblesWithWeight(min_weight)) {
      if (!T_cw.count(j) || j == k->parent || (g->children.count(i) && g->children.at(i).count(j))) continue;
      if (le != loop_edges.end() && le->second.count(j)) continue;
      if (j >= i || g->inserted.count(CorrectEdgeKey(i, j))) continue;
      add(j);
    }
  }
}

// Points follow the keyframe that corrected them, else their reference keyframe.
void CorrectMovePoints(Map& map, const std::map<int64_t, int64_t>& corrected_by, const std::map<int64_t, SE3>& T_cw,
                       const std::map<int64_t, SE3>& T_cw_optimised) {
  for (const auto& [mp, p] : map.points) {
    if (p->bad) continue;
    const auto cb = corrected_by.find(mp);
    const int64_t ref = cb != corrected_by.end() ? cb->second : p->ref_kf;
    if (!T_cw.count(ref)) continue;
    p->X_w = T_cw_optimised.at(ref).inverse() * (T_cw.at(ref) * p->X_w);
    map.UpdatePointNormalAndDepth(mp);
  }
}

}  // namespace

void LoopCloser::CorrectLoop(KeyFrame& kf, const Candidate& c, LoopEvent* event) {
  map_.UpdateConnections(kf.id);
  std::map<int64_t, SE3> T_cw_before;  // every keyframe before the correction: lines and planes follow
  if (structure_ != nullptr)
    for (const auto& [id, k] : map_.keyframes)
      if (!k->bad) T_cw_before[id] = k->T_cw;
  // The keyframe and its covisibles with their poses before and after the correction.
  const std::vector<int64_t> connected = CorrectConnectedKeyFrames(map_, kf);
  const SE3 T_wc = kf.T_cw.inverse();
  std::map<int64_t, SE3> corrected, non_corrected;
  for (int64_t id : connected) {
    const SE3 T_iw = map_.kf(id)->T_cw;
    non_corrected[id] = T_iw;
    corrected[id] = id == kf.id ? c.T_cw : SE3(T_iw * T_wc) * c.T_cw;
  }
  const std::map<int64_t, int64_t> corrected_by = CorrectKeyFramesAndPoints(map_, connected, corrected, non_corrected);
  CorrectFuseMatched(map_, kf, c.matched);
  CorrectSearchAndFuse(map_, connected, corrected, c.loop_points);
  const std::map<int64_t, std::set<int64_t>> loop_connections = CorrectLoopConnections(map_, connected);
  // Essential graph (ORB-SLAM2 Optimizer::OptimizeEssentialGraph, fixed scale).
  CorrectGraph g;
  for (const auto& [id, k] : map_.keyframes) {
    if (k->bad) continue;
    g.T_cw[id] = k->T_cw;
    if (k->parent >= 0) g.children[k->parent].insert(id);
  }
  CorrectAddLoopConnectionEdges(map_, loop_connections, kf.id, c.loop_kf, options_.essential_min_weight, &g);
  std::map<int64_t, std::set<int64_t>> loop_edges = loop_edges_;
  loop_edges[kf.id].insert(c.loop_kf);
  loop_edges[c.loop_kf].insert(kf.id);
  CorrectAddGraphEdges(map_, non_corrected, loop_edges, options_.essential_min_weight, &g);
  ++essential_calls_;
  const PoseGraphResult pg = OptimizePoseGraph(g.T_cw, {c.loop_kf}, g.edges, options_.essential_iterations, &trace_,
                                               "essential#" + std::to_string(essential_calls_));
  event->essential_chi2_start = pg.chi2_start;
  event->essential_chi2_end = pg.chi2_end;
  for (const auto& [id, T] : pg.T_cw) map_.kf(id)->T_cw = T;
  CorrectMovePoints(map_, corrected_by, g.T_cw, pg.T_cw);
  if (structure_ != nullptr) MoveStructureWithKeyFrames(map_, T_cw_before);
  loop_edges_ = std::move(loop_edges);
  if (options_.global_ba) {
    const double t0 = ThreadCpuMs();
    GlobalBundleAdjustment();
    timing_.global_ba_ms += ThreadCpuMs() - t0;
  }
}

void LoopCloser::GlobalBundleAdjustment() {
  const GlobalBAProblem p = BuildGlobalBA(map_, structure_);
  if (p.observations.empty()) return;
  ++global_ba_calls_;
  const optim::LocalBAResult r =
      optim::LocalBundleAdjust(camera_.Pinhole(), p.keyframes, p.points, p.observations,
                               structure_ != nullptr ? &p.structure : nullptr, ba_, &trace_,
                               "globalba#" + std::to_string(global_ba_calls_));
  ApplyGlobalBA(map_, p, r, structure_);
}

}  // namespace dynref::loop
