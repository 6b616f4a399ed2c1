// Loop closing's global BA problem and the structure landmarks' move; see global_ba.h.
#include "loop/global_ba.h"

#include <set>

#include "mapping/ba_observation.h"

namespace dynref::loop {

GlobalBAProblem BuildGlobalBA(const Map& map, const structure::StructureTracker* structure) {
  GlobalBAProblem p;
  std::set<int64_t> good;
  const int64_t first = map.keyframes.empty() ? -1 : map.keyframes.begin()->first;
  for (const auto& [id, k] : map.keyframes) {
    if (k->bad) continue;
    p.keyframes.push_back({id, k->T_cw, id == first});
    good.insert(id);
  }
  for (const auto& [id, pt] : map.points) {
    if (pt->bad) continue;
    std::vector<optim::BAObservation> mine;
    for (const auto& [k_id, idx] : pt->observations) {
      const KeyFrame* k = map.kf(k_id);
      if (!good.count(k_id) || k->frame.IsExcluded(idx)) continue;
      mine.push_back(KeyframeObservation(*k, k_id, id, idx));
    }
    if (mine.empty()) continue;
    p.points.push_back({id, pt->X_w});
    p.observations.insert(p.observations.end(), mine.begin(), mine.end());
  }
  if (structure != nullptr) {
    std::set<int64_t> fixed;  // stays empty: every good keyframe is in the problem
    structure->FillLocalBA(map, good, &fixed, &p.structure);
  }
  return p;
}

void ApplyGlobalBA(Map& map, const GlobalBAProblem& p, const optim::LocalBAResult& r,
                   const structure::StructureTracker* structure) {
  for (const optim::BAKeyFrame& k : p.keyframes) {
    const auto it = r.T_cw.find(k.id);
    if (!k.fixed && it != r.T_cw.end()) map.kf(k.id)->T_cw = it->second;
  }
  for (const optim::BAPoint& pt : p.points) {
    const auto it = r.X_w.find(pt.id);
    if (it == r.X_w.end()) continue;
    map.mp(pt.id)->X_w = it->second;
    map.UpdatePointNormalAndDepth(pt.id);
  }
  if (structure != nullptr) structure->ApplyLandmarks(map, r);
}

namespace {

// The world change a landmark of keyframe `kf` undergoes: X' = T_cw_now^-1 T_cw_before X.
bool GlobalBaLandmarkMove(const Map& map, const std::map<int64_t, SE3>& T_cw_before, int64_t kf, SE3* move) {
  const KeyFrame* k = map.kf(kf);
  const auto before = T_cw_before.find(kf);
  if (k == nullptr || k->bad || before == T_cw_before.end()) return false;
  *move = SE3(k->T_cw.inverse() * before->second);
  return true;
}

}  // namespace

void MoveStructureWithKeyFrames(Map& map, const std::map<int64_t, SE3>& T_cw_before) {
  for (auto& [id, L] : map.lines) {
    SE3 M;
    if (L->bad || !GlobalBaLandmarkMove(map, T_cw_before, L->first_kf, &M)) continue;
    L->P_s = M * L->P_s;
    L->P_e = M * L->P_e;
  }
  for (auto& [id, P] : map.planes) {
    SE3 M;
    if (P->bad || !GlobalBaLandmarkMove(map, T_cw_before, P->first_kf, &M)) continue;
    // n^T X + d = 0 with X = M^-1 X': n' = R n, d' = d - n'^T t.
    const Eigen::Vector3d n = (M.linear() * P->n).normalized();
    P->d = P->d - n.dot(M.translation());
    P->n = n;
  }
}

}  // namespace dynref::loop
