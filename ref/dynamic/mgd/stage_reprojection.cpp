// mgd.reprojection (kOnMapUpdate): seed 000 Sec. 3.5 long-term cue P_pro, computed for the map
// points of a new keyframe KF_k once local mapping has connected it (spec step 15 says "when a
// keyframe is created"; its covisibility exists only after local mapping's UpdateConnections).
// For each map point X of KF_k and each keyframe j in the 1st + 2nd order covisibility of KF_k
// (spec E8) that observes X at u_j:
//   forward  d_jk = || pi(K, T_jw X) - u_j ||
//   backward d_kj = || pi(K, T_kw T_jw^-1 Z_j(u_j) K^-1 [u_j 1]) - u_k ||  (u_j with KF j's depth;
//            skipped when u_j has no depth)
//   P_pro = sig(a_pro ((mean_j d_jk + mean_j d_kj) / 2 - d_th_pro)); K_n = number of such j.
// Cached per map point (the last keyframe's value wins) and kept valid through landmark events:
// a replaced point's value moves to its replacement (unless that has its own), a culled one is
// dropped.
#include <set>

#include "dynamic/mgd/probability.h"
#include "dynamic/mgd/stages.h"

namespace dynref::mgd {
namespace {

// 1st + 2nd order covisible keyframes of kf (not kf itself), ascending id.
std::set<int64_t> Covisibility(const Map& map, const KeyFrame& kf) {
  std::set<int64_t> out;
  for (int64_t a : kf.ordered_covisibles) {
    const KeyFrame* ka = map.kf(a);
    if (ka == nullptr || ka->bad) continue;
    out.insert(a);
    for (int64_t b : ka->ordered_covisibles) {
      const KeyFrame* kb = map.kf(b);
      if (kb != nullptr && !kb->bad) out.insert(b);
    }
  }
  out.erase(kf.id);
  return out;
}

bool Project(const Intrinsics& K, const SE3& T_cw, const Eigen::Vector3d& X_w, Eigen::Vector2d* uv) {
  const Eigen::Vector3d X_c = T_cw * X_w;
  if (X_c.z() <= 0) return false;
  *uv = K.Project(X_c);
  return true;
}

}  // namespace

void ReprojectionStage::Run(StageContext& ctx) {
  const MgdOptions& o = RequireOptions(*state_, name());
  const KeyFrame* kf = ctx.new_keyframe;
  if (kf == nullptr || kf->bad) return;
  const Intrinsics K = ctx.camera.Pinhole();
  const std::set<int64_t> cov = Covisibility(ctx.map, *kf);
  const bool full = ctx.trace.full_enabled();
  int64_t computed = 0;
  for (size_t k_idx = 0; k_idx < kf->map_point_ids.size(); ++k_idx) {
    const MapPoint* X = ctx.map.good_mp(kf->map_point_ids[k_idx]);
    if (X == nullptr) continue;
    const cv::Point2f& u_k = kf->frame.keys_un[k_idx].pt;
    double fwd = 0, bwd = 0;
    int n_fwd = 0, n_bwd = 0;
    for (const auto& [j_id, j_idx] : X->observations) {
      if (!cov.count(j_id)) continue;
      const KeyFrame* kj = ctx.map.kf(j_id);
      const cv::Point2f& u_j = kj->frame.keys_un[j_idx].pt;
      Eigen::Vector2d proj;
      if (Project(K, kj->T_cw, X->X_w, &proj)) {
        fwd += (proj - Eigen::Vector2d(u_j.x, u_j.y)).norm();
        ++n_fwd;
      }
      const float z_j = kj->frame.depth[j_idx];
      if (z_j > 0) {
        const Eigen::Vector3d X_w = kj->T_cw.inverse() * K.Backproject(u_j.x, u_j.y, z_j);
        if (Project(K, kf->T_cw, X_w, &proj)) {
          bwd += (proj - Eigen::Vector2d(u_k.x, u_k.y)).norm();
          ++n_bwd;
        }
      }
    }
    if (n_fwd == 0) continue;  // not computable: no covisible keyframe observes the point
    ProCue cue;
    cue.mean_forward_px = fwd / n_fwd;
    cue.mean_backward_px = n_bwd > 0 ? bwd / n_bwd : cue.mean_forward_px;  // no depth: forward only
    cue.covisible = n_fwd;
    cue.kf = kf->id;
    cue.mp = X->id;
    cue.p = ProbabilityPro(cue.mean_forward_px, cue.mean_backward_px, o);
    state_->pro[X->id] = cue;
    ++computed;
    if (full)
      ctx.trace.ProbabilityUpdate(name(), trace::EntityKind::kMapPoint, "mp" + std::to_string(X->id),
                                  {{"kf", double(kf->id)}, {"covisible", double(n_fwd)},
                                   {"with_depth", double(n_bwd)}, {"mean_forward_px", cue.mean_forward_px},
                                   {"mean_backward_px", cue.mean_backward_px}},
                                  0.5, cue.p);
  }
  ctx.trace.FrameCount(name(), "covisible_keyframes", static_cast<int64_t>(cov.size()));
  ctx.trace.FrameCount(name(), "P_pro_computed", computed);
}

void ReprojectionStage::OnLandmarkEvent(const LandmarkEvent& e) {
  if (e.landmark.type != LandmarkType::kPoint) return;
  auto it = state_->pro.find(e.landmark.id);
  if (it == state_->pro.end()) return;
  if (e.kind == LandmarkEvent::Kind::kReplaced) state_->pro.emplace(e.by_id, it->second);  // keeps by_id's own
  if (e.kind != LandmarkEvent::Kind::kCreated) state_->pro.erase(it);
}

}  // namespace dynref::mgd
