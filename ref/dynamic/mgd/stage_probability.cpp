// mgd.probability (kBeforeFinalPose, i.e. after the local-map search; kAfterInitialPose with
// after_local_map_search: false): seed 000 Sec. 3.4-3.6, spec steps 7-13 for points and step 11
// for line samples (line_samples.h; they share the diffusion with the points).
// Per non-excluded feature: inherited P_prev (previous-frame feature, else its map point, else
// P_init by Flag_d), the cues P_LS (short-term velocity deviation from the out-of-box mean flow),
// P_pro (cached per map point by mgd.reprojection) and P_mf (distance to the epipolar line of F
// from the initial relative pose), log-odds fusion S, smoothing, Jacobi diffusion over 3-D
// neighbours within radius_m, then suppression (P > tau_dyn) or weight w = 1 - P. P is written
// back to the frame's features (next frame's inheritance) and to the matched map points.
#include <Eigen/Core>

#include "dynamic/mgd/correspondence.h"
#include "dynamic/mgd/line_samples.h"
#include "dynamic/mgd/probability.h"
#include "dynamic/mgd/stages.h"
#include "geometry/fundamental.h"

namespace dynref::mgd {

ProbabilityStage::ProbabilityStage(const MgdOptions& o, std::shared_ptr<MgdState> state)
    : o_(o), state_(std::move(state)) {
  state_->options = o;
  state_->configured = true;
}

namespace {

// Mean image velocity of the out-of-box features with a previous-frame correspondence (spec E6).
int MeanBackgroundVelocity(const Frame& f, const Frame& prev, const std::vector<Correspondence>& corr,
                           const std::vector<uint8_t>& in_box, Eigen::Vector2d* vbar) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (size_t i = 0; i < f.N(); ++i) {
    if (corr[i].prev_index < 0 || in_box[i]) continue;
    const cv::Point2f d = f.keys_un[i].pt - prev.keys_un[corr[i].prev_index].pt;
    sum += Eigen::Vector2d(d.x, d.y);
    ++n;
  }
  if (n == 0) return 0;
  *vbar = sum / n;
  return n;  // features in the mean
}

// Per frame (issue 32): what the cues of every feature share, so `trace verify` can recompute
// them: the previous frame, the mean background flow and the previous frame's pose as this stage
// saw it (the tracker moves it with its reference keyframe, so it can differ from that frame's
// final POSE record); F follows from it and this frame's initial POSE.
void TraceFrameInputs(trace::TraceWriter& tr, const Frame& f, const Frame* prev, int n_vbar, const Eigen::Vector2d& vbar,
                      bool has_T, bool has_F) {
  std::vector<trace::NamedValue> in = {{"prev_frame", prev ? double(prev->index) : -1.0},
                                       {"n_vbar", double(n_vbar)}, {"vbar_u", vbar.x()}, {"vbar_v", vbar.y()},
                                       {"has_T", has_T ? 1.0 : 0.0}, {"has_F", has_F ? 1.0 : 0.0}};
  if (has_T) {
    static const char* kNames[12] = {"prev_T_cw[0]", "prev_T_cw[1]", "prev_T_cw[2]", "prev_T_cw[3]",
                                     "prev_T_cw[4]", "prev_T_cw[5]", "prev_T_cw[6]", "prev_T_cw[7]",
                                     "prev_T_cw[8]", "prev_T_cw[9]", "prev_T_cw[10]", "prev_T_cw[11]"};
    const Eigen::Matrix4d M = prev->T_cw.matrix();
    for (int i = 0; i < 12; ++i) in.push_back({kNames[i], M(i / 4, i % 4)});
  }
  tr.ProbabilityUpdate("mgd.frame", trace::EntityKind::kFrame, "f" + std::to_string(f.index), in, 0.0, 0.0);
}

// What the cues of every feature share this frame: the previous-frame correspondences, the mean
// background flow (spec E6) and F of the initial relative pose (spec E9).
struct ProbStageFrameCues {
  const Frame* prev = nullptr;
  std::vector<Correspondence> corr;
  bool have_prev_p = false;
  Eigen::Vector2d vbar = Eigen::Vector2d::Zero();
  int n_vbar = 0;
  bool has_vbar = false, has_F = false, has_T = false;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  SE3 T_cur_prev = SE3::Identity();
};

ProbStageFrameCues ProbStagePrepareFrame(StageContext& ctx, const MgdOptions& o, const MgdState& s, const Frame& f) {
  ProbStageFrameCues fc;
  const Frame* prev = ctx.previous;
  fc.prev = prev;
  fc.corr.resize(f.N());
  if (prev != nullptr) fc.corr = MatchPrevious(f, *prev, o.delta, o.match_radius_px, ctx.threads);
  fc.have_prev_p = prev != nullptr && s.prev_frame == prev->index && s.prev_p.size() == prev->N();
  fc.n_vbar = prev != nullptr ? MeanBackgroundVelocity(f, *prev, fc.corr, s.in_box, &fc.vbar) : 0;
  fc.has_vbar = fc.n_vbar > 0;
  // F of the initial relative pose (spec E9: the line in frame k is F x^{k-1}).
  if (prev != nullptr && prev->has_pose && f.has_pose) {
    fc.T_cur_prev = f.T_cw * prev->T_cw.inverse();
    fc.has_T = true;
    if (fc.T_cur_prev.translation().norm() > 1e-9) {
      const Intrinsics K = ctx.camera.Pinhole();
      Eigen::Matrix3d Km;
      Km << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
      fc.F = geometry::FundamentalFromPose(Km, fc.T_cur_prev.linear(), fc.T_cur_prev.translation());
      fc.has_F = true;
    }
  }
  return fc;
}

// The diffusion nodes (features first, then 3 samples per line) and the frame's counters.
struct ProbStageNodes {
  std::vector<double> p_smooth;
  std::vector<Eigen::Vector3d> points;
  std::vector<bool> has_point;
  int64_t counts[3] = {0, 0, 0}, computable_ls = 0, computable_pro = 0, computable_mf = 0;
};

// Step 7: inheritance (previous-frame feature, else its map point, else P_init by Flag_d).
double ProbStageInherit(StageContext& ctx, const MgdOptions& o, const MgdState& s, const ProbStageFrameCues& fc,
                        size_t i, int j, int64_t mp, int* source) {
  double p_prev;
  const MapPoint* point = mp >= 0 ? ctx.map.mp(mp) : nullptr;
  if (j >= 0 && fc.have_prev_p && s.prev_p[j] >= 0) {
    p_prev = s.prev_p[j], *source = 0;
  } else if (point != nullptr && point->dynamic.p_dynamic >= 0) {
    p_prev = point->dynamic.p_dynamic, *source = 1;
  } else {
    p_prev = s.in_box[i] ? o.p_init_box : o.p_init_free, *source = 2;
  }
  return p_prev;
}

struct ProbStageFeatureCues {
  Cues c;
  VelocityDeviation dev;
  double d_epi = 0;
  const ProCue* pro = nullptr;
};

// Step 8: cues P_LS, P_pro and P_mf of feature i.
ProbStageFeatureCues ProbStageCues(const MgdOptions& o, const MgdState& s, const Frame& f, const ProbStageFrameCues& fc,
                                   size_t i, int j, int64_t mp) {
  ProbStageFeatureCues q;
  Cues& c = q.c;
  if (j >= 0 && fc.has_vbar) {
    const cv::Point2f d = f.keys_un[i].pt - fc.prev->keys_un[j].pt;
    q.dev = Deviation(Eigen::Vector2d(d.x, d.y), fc.vbar, o);
    c.has_ls = true;
    c.p_ls = ProbabilityLS(q.dev, o);
  }
  if (mp >= 0) {
    auto it = s.pro.find(mp);
    if (it != s.pro.end()) q.pro = &it->second, c.has_pro = true, c.p_pro = it->second.p;
  }
  if (j >= 0 && fc.has_F) {
    const cv::Point2f a = fc.prev->keys_un[j].pt, b = f.keys_un[i].pt;
    q.d_epi = geometry::EpipolarDistance(fc.F, Eigen::Vector2d(a.x, a.y), Eigen::Vector2d(b.x, b.y));
    c.has_mf = true;
    c.p_mf = ProbabilityMF(q.d_epi, o);
  }
  return q;
}

void ProbStageTraceFeature(trace::TraceWriter& tr, const MgdOptions& o, const MgdState& s, const ProbStageFrameCues& fc,
                           size_t i, const std::string& id, int source, int j, int64_t mp, double p_prev,
                           const ProbStageFeatureCues& q, double S, double p_smooth) {
  const Cues& c = q.c;
  const ProCue* pro = q.pro;
  tr.ProbabilityUpdate("mgd.inherit", trace::EntityKind::kFeature, id,
                       {{"source", double(source)}, {"prev_index", double(j)}, {"map_point", double(mp)},
                        {"in_box", double(s.in_box[i])}, {"hamming", double(fc.corr[i].hamming)}},
                       p_prev, p_prev);
  tr.ProbabilityUpdate("mgd.P_LS", trace::EntityKind::kFeature, id,
                       {{"computable", double(c.has_ls)}, {"d_px", q.dev.d_px}, {"dtheta", q.dev.dtheta},
                        {"vbar_u", fc.vbar.x()}, {"vbar_v", fc.vbar.y()}},
                       0.5, c.has_ls ? c.p_ls : 0.5);
  tr.ProbabilityUpdate("mgd.P_pro", trace::EntityKind::kFeature, id,
                       {{"computable", double(c.has_pro)}, {"mean_forward_px", pro ? pro->mean_forward_px : 0.0},
                        {"mean_backward_px", pro ? pro->mean_backward_px : 0.0},
                        {"covisible", pro ? double(pro->covisible) : 0.0}, {"kf", pro ? double(pro->kf) : -1.0},
                        {"source_mp", pro ? double(pro->mp) : -1.0}},
                       0.5, c.has_pro ? c.p_pro : 0.5);
  tr.ProbabilityUpdate("mgd.P_mf", trace::EntityKind::kFeature, id,
                       {{"computable", double(c.has_mf)}, {"d_epi_px", q.d_epi}}, 0.5, c.has_mf ? c.p_mf : 0.5);
  tr.ProbabilityUpdate("mgd.fusion", trace::EntityKind::kFeature, id,
                       {{"w_ls", o.use_ls ? o.w_ls : 0.0}, {"w_pro", o.use_pro ? o.w_pro : 0.0},
                        {"w_mf", o.use_mf ? o.w_mf : 0.0}},
                       0.5, S);
  tr.ProbabilityUpdate("mgd.smooth", trace::EntityKind::kFeature, id, {{"S", S}, {"a", o.a}}, p_prev, p_smooth);
}

// Steps 7-9 for every non-excluded feature: inherited P, cues, fusion and smoothing; the
// feature's 3-D point (camera frame) for the diffusion.
ProbStageNodes ProbStageFeatureNodes(StageContext& ctx, const MgdOptions& o, const MgdState& s, const Frame& f,
                                     const ProbStageFrameCues& fc, bool full) {
  const size_t n = f.N();
  ProbStageNodes nodes;
  nodes.p_smooth.assign(n, -1.0);
  nodes.points.assign(n, Eigen::Vector3d::Zero());
  nodes.has_point.assign(n, false);
  const Intrinsics K = ctx.camera.Pinhole();
  for (size_t i = 0; i < n; ++i) {
    const int fi = static_cast<int>(i);
    if (f.IsExcluded(fi)) continue;
    const std::string id = f.FeatureId(fi);
    const int j = fc.corr[i].prev_index;
    const int64_t mp = f.outlier[i] ? -1 : f.map_point_ids[i];
    int source;
    const double p_prev = ProbStageInherit(ctx, o, s, fc, i, j, mp, &source);
    ++nodes.counts[source];
    const ProbStageFeatureCues q = ProbStageCues(o, s, f, fc, i, j, mp);
    nodes.computable_ls += q.c.has_ls, nodes.computable_pro += q.c.has_pro, nodes.computable_mf += q.c.has_mf;
    const double S = Fuse(q.c, o);
    nodes.p_smooth[i] = Smooth(p_prev, S, o);
    if (f.depth[i] > 0) {
      nodes.points[i] = K.Backproject(f.keys_un[i].pt.x, f.keys_un[i].pt.y, f.depth[i]);
      nodes.has_point[i] = true;
    }
    if (full) ProbStageTraceFeature(ctx.trace, o, s, fc, i, id, source, j, mp, p_prev, q, S, nodes.p_smooth[i]);
  }
  return nodes;
}

// Step 10 nodes: after the n features in index order, 3 samples per line.
void ProbStageAppendLineNodes(const LineSampleNodes& lines, ProbStageNodes* nodes) {
  for (size_t i = 0; i < lines.size(); ++i)
    for (size_t k = 0; k < 3; ++k) {
      nodes->points.push_back(lines.X[i][k]);
      nodes->has_point.push_back(lines.has_X[i][k]);
      nodes->p_smooth.push_back(lines.p_smooth[i][k]);
    }
}

// Steps 13 and 15 for the features: suppression / weights, write-back to the matched map points;
// fills next_prev (the next frame's inheritance) and returns the number suppressed.
int64_t ProbStageDecideFeatures(StageContext& ctx, const MgdOptions& o, const Frame& f, const ProbStageNodes& nodes,
                                const std::vector<double>& p, const std::vector<int>& neighbours,
                                const std::string& stage, bool full, std::vector<double>* next_prev) {
  trace::TraceWriter& tr = ctx.trace;
  int64_t suppressed = 0;
  for (size_t i = 0; i < next_prev->size(); ++i) {
    const int fi = static_cast<int>(i);
    if (nodes.p_smooth[i] < 0) continue;  // excluded before this stage
    (*next_prev)[i] = p[i];
    const bool suppress = p[i] > o.tau_dyn;
    const double w = suppress ? 0.0 : KeptWeight(p[i], o);
    if (full) {  // the node's 3-D point (camera frame): the diffusion is recomputable (issue 32)
      const Eigen::Vector3d& X = nodes.points[i];
      tr.ProbabilityUpdate("mgd.diffuse", trace::EntityKind::kFeature, f.FeatureId(fi),
                           {{"neighbours", double(neighbours[i])}, {"weight", w}, {"has_point", nodes.has_point[i] ? 1.0 : 0.0},
                            {"x", X.x()}, {"y", X.y()}, {"z", X.z()}},
                           nodes.p_smooth[i], p[i]);
    }
    const int64_t mp = f.outlier[i] ? -1 : f.map_point_ids[i];
    if (mp >= 0 && ctx.map.mp(mp) != nullptr) {
      if (full) {  // the map point's P (what a later frame's inheritance reads), issue 32
        const double old_p = ctx.map.mp(mp)->dynamic.p_dynamic;
        tr.ProbabilityUpdate("mgd.map_point", trace::EntityKind::kMapPoint, "mp" + std::to_string(mp),
                             {{"feature", double(i)}, {"had_p", old_p >= 0 ? 1.0 : 0.0}}, old_p >= 0 ? old_p : p[i], p[i]);
      }
      ctx.frame.SetPointDynamicProbability(mp, p[i], stage);
    }
    if (suppress) {
      ctx.frame.Exclude(fi, stage, "p>tau_dyn");
      ++suppressed;
    } else {
      ctx.frame.SetWeight(fi, w);
      tr.Decision(stage, trace::EntityKind::kFeature, f.FeatureId(fi), true, "p<=tau_dyn");
    }
  }
  return suppressed;
}

void ProbStageFrameCounts(trace::TraceWriter& tr, const std::string& stage, const ProbStageNodes& nodes,
                          int64_t suppressed) {
  tr.FrameCount(stage, "inherit_prev_frame", nodes.counts[0]);
  tr.FrameCount(stage, "inherit_map_point", nodes.counts[1]);
  tr.FrameCount(stage, "inherit_init", nodes.counts[2]);
  tr.FrameCount(stage, "P_LS_computable", nodes.computable_ls);
  tr.FrameCount(stage, "P_pro_computable", nodes.computable_pro);
  tr.FrameCount(stage, "P_mf_computable", nodes.computable_mf);
  tr.FrameCount(stage, "suppressed", suppressed);
}

}  // namespace

void ProbabilityStage::Run(StageContext& ctx) {
  const MgdOptions& o = o_;
  MgdState& s = *state_;
  const Frame& f = ctx.frame.view();
  if (s.frame != f.index) throw std::logic_error("mgd.probability needs mgd.boxes earlier in the stage list");
  trace::TraceWriter& tr = ctx.trace;
  const bool full = tr.full_enabled();
  const size_t n = f.N();
  const ProbStageFrameCues fc = ProbStagePrepareFrame(ctx, o, s, f);
  if (full) TraceFrameInputs(tr, f, fc.prev, fc.n_vbar, fc.vbar, fc.has_T, fc.has_F);
  ProbStageNodes nodes = ProbStageFeatureNodes(ctx, o, s, f, fc, full);
  // Step 11: line samples through steps 7-9 (line_samples.h).
  const LineSampleNodes lines = EvaluateLineSamples(ctx, o, s, fc.has_vbar ? &fc.vbar : nullptr, fc.has_F ? &fc.F : nullptr,
                                                    fc.has_T ? &fc.T_cur_prev : nullptr, name());
  // Step 10: diffusion (Jacobi) over the features and line samples with a 3-D point; nodes are
  // the n features in index order, then 3 samples per line.
  ProbStageAppendLineNodes(lines, &nodes);
  std::vector<int> neighbours(nodes.p_smooth.size(), 0);
  const std::vector<double> p = o.diffusion ? Diffuse(nodes.points, nodes.has_point, nodes.p_smooth, o.radius_m,
                                                      &neighbours, ctx.threads)
                                            : nodes.p_smooth;
  // Steps 13 and 15: suppression / weights, write-back.
  std::vector<double> next_prev(n, -1.0);
  const int64_t suppressed = ProbStageDecideFeatures(ctx, o, f, nodes, p, neighbours, name(), full, &next_prev);
  DecideLines(ctx, o, s, lines, std::vector<double>(p.begin() + static_cast<std::ptrdiff_t>(n), p.end()),
              std::vector<int>(neighbours.begin() + static_cast<std::ptrdiff_t>(n), neighbours.end()), name());
  s.prev_frame = f.index;
  s.prev_p = std::move(next_prev);
  ProbStageFrameCounts(tr, name(), nodes, suppressed);
}

}  // namespace dynref::mgd
