#include "dynamic/mgd/line_samples.h"

#include <algorithm>
#include <cmath>

#include "dynamic/mgd/probability.h"
#include "dynamic/mgd/stages.h"
#include "geometry/fundamental.h"

namespace dynref::mgd {
namespace {

std::array<Eigen::Vector2d, 3> SamplePixels(const FrameLine& L) { return {L.s, 0.5 * (L.s + L.e), L.e}; }

// A line above tau_dyn by its largest sample: weight 0 (out); else the kept weight.
double LineWeight(double p_max, const MgdOptions& o) { return p_max > o.tau_dyn ? 0.0 : KeptWeight(p_max, o); }

}  // namespace

std::vector<std::array<uint8_t, 3>> LineSampleBoxFlags(const Frame& f, const MgdOptions& o) {
  std::vector<std::array<uint8_t, 3>> flags(f.structure.lines.size(), {0, 0, 0});
  for (size_t i = 0; i < flags.size(); ++i) {
    const auto px = SamplePixels(f.structure.lines[i]);
    for (size_t k = 0; k < 3; ++k)
      flags[i][k] = InKeptBox(f.detections, o, static_cast<float>(px[k].x()), static_cast<float>(px[k].y())) ? 1 : 0;
  }
  return flags;
}

void InitialiseLinePriors(StageContext& ctx, const MgdOptions& o, MgdState& s) {
  const size_t n = s.line_in_box.size();
  s.prev_line_p.assign(n, {-1.0, -1.0, -1.0});
  trace::TraceWriter& tr = ctx.trace;
  const bool full = tr.full_enabled();
  const int frame = ctx.frame.view().index;
  for (size_t i = 0; i < n; ++i) {
    double p_max = 0;
    const std::string id = full ? FrameStructure::LineId(frame, static_cast<int>(i)) : std::string();
    for (size_t k = 0; k < 3; ++k) {
      s.prev_line_p[i][k] = s.line_in_box[i][k] ? o.p_init_box : o.p_init_free;
      p_max = std::max(p_max, s.prev_line_p[i][k]);
      if (full)  // each sample's first P (issue 32: the next frame's inheritance reads it)
        tr.ProbabilityUpdate("mgd.boxes", trace::EntityKind::kLineSample, id,
                             {{"sample", double(k)}, {"in_box", double(s.line_in_box[i][k])}}, s.prev_line_p[i][k],
                             s.prev_line_p[i][k]);
    }
    const double w = LineWeight(p_max, o);
    if (full)  // the line: its largest sample and weight (no input "sample")
      tr.ProbabilityUpdate("mgd.boxes", trace::EntityKind::kLineSample, id, {{"weight", w}}, p_max, p_max);
    ctx.frame.SetLineWeight(static_cast<int>(i), w);
  }
}

namespace {

// What every line sample's steps 7-9 share this frame.
struct LineEvalFrame {
  const Frame& f;
  const Frame* prev;
  const MgdOptions& o;
  const MgdState& s;
  bool have_prev_p;
  Intrinsics K;
  const Eigen::Vector2d* vbar;
  const Eigen::Matrix3d* F;
  const SE3* T_cur_prev;
};

LineSampleNodes LineEvalEmptyNodes(size_t n) {
  LineSampleNodes out;
  out.p_prev.assign(n, {-1.0, -1.0, -1.0});
  out.p_smooth.assign(n, {-1.0, -1.0, -1.0});
  out.X.assign(n, {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  out.has_X.assign(n, {false, false, false});
  out.corr.assign(n, structure::LineCorrespondence{});
  return out;
}

// Step 7: inheritance (previous line sample, else the map line, else P_init(Flag_d)).
double LineEvalInherit(const LineEvalFrame& e, const structure::LineCorrespondence& c, const MapLine* map_line,
                       size_t i, size_t k, size_t kp, int* source) {
  double p_prev;
  if (c.prev_index >= 0 && e.have_prev_p && e.s.prev_line_p[static_cast<size_t>(c.prev_index)][kp] >= 0) {
    p_prev = e.s.prev_line_p[static_cast<size_t>(c.prev_index)][kp], *source = 0;
  } else if (map_line != nullptr && map_line->dynamic.p_dynamic >= 0) {
    p_prev = map_line->dynamic.p_dynamic, *source = 1;
  } else {
    p_prev = e.s.line_in_box[i][k] ? e.o.p_init_box : e.o.p_init_free, *source = 2;
  }
  return p_prev;
}

struct LineEvalCues {
  Cues cues;
  VelocityDeviation dev;
  double d_mf = 0;
};

// Step 8: cues of sample k (E12: pseudo-point or normal form; P_pro not computed for lines).
LineEvalCues LineEvalSampleCues(const LineEvalFrame& e, const FrameLine& L, const structure::LineCorrespondence& c,
                                const std::array<Eigen::Vector2d, 3>& px,
                                const std::array<Eigen::Vector2d, 3>& prev_px, size_t k, size_t kp) {
  const MgdOptions& o = e.o;
  LineEvalCues q;
  Cues& cues = q.cues;
  const Eigen::Vector3d l = L.l;
  const bool has_line = l.head<2>().squaredNorm() > 0;
  if (c.prev_index >= 0 && e.vbar != nullptr) {
    if (o.line_cue_form == LineCueForm::kPseudoPoint) {
      q.dev = Deviation(px[k] - prev_px[kp], *e.vbar, o);
    } else if (has_line) {
      // Normal flow: n . (x^k - x^{k-1}) = -l . x^{k-1} for x^k on the current line.
      q.dev.d_px = std::fabs(l.dot(Eigen::Vector3d(prev_px[kp].x(), prev_px[kp].y(), 1.0)) + l.head<2>().dot(*e.vbar));
      q.dev.dtheta = o.theta_th_ls_rad;
    }
    cues.has_ls = o.line_cue_form == LineCueForm::kPseudoPoint || has_line;
    if (cues.has_ls) cues.p_ls = ProbabilityLS(q.dev, o);
  }
  if (c.prev_index >= 0) {
    if (o.line_cue_form == LineCueForm::kPseudoPoint && e.F != nullptr) {
      q.d_mf = geometry::EpipolarDistance(*e.F, prev_px[kp], px[k]);
      cues.has_mf = true;
    } else if (o.line_cue_form == LineCueForm::kNormal && e.T_cur_prev != nullptr && has_line) {
      const FrameLine& P = e.prev->structure.lines[static_cast<size_t>(c.prev_index)];
      if (P.sample_depth[kp]) {
        const Eigen::Vector3d Xk = *e.T_cur_prev * P.X_c[kp];
        if (Xk.z() > 0) {
          const Eigen::Vector2d u = e.K.Project(Xk);
          q.d_mf = std::fabs(l.dot(Eigen::Vector3d(u.x(), u.y(), 1.0)));
          cues.has_mf = true;
        }
      }
    }
    if (cues.has_mf) cues.p_mf = ProbabilityMF(q.d_mf, o);
  }
  return q;
}

// The six records of one sample's steps 7-9 (full trace).
void LineEvalTraceSample(trace::TraceWriter& tr, const LineEvalFrame& e, const std::string& id,
                         const structure::LineCorrespondence& c, int64_t ml, size_t i, size_t k, size_t kp, int source,
                         double p_prev, const LineEvalCues& q, double S, double p_smooth) {
  const MgdOptions& o = e.o;
  const Eigen::Vector2d* vbar = e.vbar;
  const double sample = static_cast<double>(k), mld = static_cast<double>(ml);
  const trace::EntityKind kind = trace::EntityKind::kLineSample;
  tr.ProbabilityUpdate("mgd.inherit", kind, id,
                       {{"sample", sample}, {"source", double(source)}, {"prev_index", double(c.prev_index)},
                        {"prev_sample", double(kp)}, {"map_line", mld}, {"in_box", double(e.s.line_in_box[i][k])},
                        {"hamming", double(c.hamming)}, {"match", double(c.source)}},
                       p_prev, p_prev);
  tr.ProbabilityUpdate("mgd.P_LS", kind, id,
                       {{"sample", sample}, {"computable", double(q.cues.has_ls)}, {"d_px", q.dev.d_px},
                        {"dtheta", q.dev.dtheta}, {"map_line", mld}, {"vbar_u", vbar ? vbar->x() : 0.0},
                        {"vbar_v", vbar ? vbar->y() : 0.0}},
                       0.5, q.cues.has_ls ? q.cues.p_ls : 0.5);
  tr.ProbabilityUpdate("mgd.P_pro", kind, id, {{"sample", sample}, {"computable", 0.0}}, 0.5, 0.5);
  tr.ProbabilityUpdate("mgd.P_mf", kind, id,
                       {{"sample", sample}, {"computable", double(q.cues.has_mf)}, {"d_px", q.d_mf}, {"map_line", mld}},
                       0.5, q.cues.has_mf ? q.cues.p_mf : 0.5);
  tr.ProbabilityUpdate("mgd.fusion", kind, id,
                       {{"sample", sample}, {"w_ls", o.use_ls ? o.w_ls : 0.0}, {"w_pro", o.use_pro ? o.w_pro : 0.0},
                        {"w_mf", o.use_mf ? o.w_mf : 0.0}},
                       0.5, S);
  tr.ProbabilityUpdate("mgd.smooth", kind, id, {{"sample", sample}, {"S", S}, {"a", o.a}, {"map_line", mld}},
                       p_prev, p_smooth);
}

// Steps 7-9 for the three samples of frame line i.
void LineEvalLine(StageContext& ctx, const LineEvalFrame& e, size_t i, bool full, LineSampleNodes* out,
                  int64_t counts[3]) {
  const FrameStructure& fs = e.f.structure;
  const FrameLine& L = fs.lines[i];
  const structure::LineCorrespondence& c = out->corr[i];
  const int64_t ml = i < fs.map_line_ids.size() ? fs.map_line_ids[i] : -1;
  const MapLine* map_line = ml >= 0 ? ctx.map.good_line(ml) : nullptr;
  const auto px = SamplePixels(L);
  const std::array<Eigen::Vector2d, 3> prev_px =
      c.prev_index >= 0 ? SamplePixels(e.prev->structure.lines[static_cast<size_t>(c.prev_index)])
                        : std::array<Eigen::Vector2d, 3>{};
  const std::string id = FrameStructure::LineId(e.f.index, static_cast<int>(i));
  for (size_t k = 0; k < 3; ++k) {
    const size_t kp = c.reversed ? 2 - k : k;  // the previous line's matching sample
    int source;
    const double p_prev = LineEvalInherit(e, c, map_line, i, k, kp, &source);
    ++counts[source];
    const LineEvalCues q = LineEvalSampleCues(e, L, c, px, prev_px, k, kp);
    const double S = Fuse(q.cues, e.o);
    out->p_prev[i][k] = p_prev;
    out->p_smooth[i][k] = Smooth(p_prev, S, e.o);
    if (L.sample_depth[k]) out->X[i][k] = L.X_c[k], out->has_X[i][k] = true;
    if (full) LineEvalTraceSample(ctx.trace, e, id, c, ml, i, k, kp, source, p_prev, q, S, out->p_smooth[i][k]);
  }
}

}  // namespace

LineSampleNodes EvaluateLineSamples(StageContext& ctx, const MgdOptions& o, const MgdState& s,
                                    const Eigen::Vector2d* vbar, const Eigen::Matrix3d* F, const SE3* T_cur_prev,
                                    const std::string& stage) {
  const Frame& f = ctx.frame.view();
  const FrameStructure& fs = f.structure;
  const size_t n = fs.lines.size();
  LineSampleNodes out = LineEvalEmptyNodes(n);
  if (n == 0) return out;
  const Frame* prev = ctx.previous;
  const bool have_prev = prev != nullptr && !prev->structure.lines.empty();
  if (have_prev) {
    structure::LineMatchGates g;
    g.angle_rad = o.line_match_angle_deg * M_PI / 180.0;
    g.radius_px = o.line_match_radius_px;
    g.max_bits = o.line_match_bits;
    out.corr = structure::MatchLinesToPrevious(fs, prev->structure, g);
  }
  const bool have_prev_p = have_prev && s.prev_frame == prev->index && s.prev_line_p.size() == prev->structure.lines.size();
  const LineEvalFrame e{f, prev, o, s, have_prev_p, ctx.camera.Pinhole(), vbar, F, T_cur_prev};
  trace::TraceWriter& tr = ctx.trace;
  const bool full = tr.full_enabled();
  int64_t counts[3] = {0, 0, 0};
  for (size_t i = 0; i < n; ++i) LineEvalLine(ctx, e, i, full, &out, counts);
  tr.FrameCount(stage, "line_inherit_prev_frame", counts[0]);
  tr.FrameCount(stage, "line_inherit_map_line", counts[1]);
  tr.FrameCount(stage, "line_inherit_init", counts[2]);
  return out;
}

int64_t DecideLines(StageContext& ctx, const MgdOptions& o, MgdState& s, const LineSampleNodes& nodes,
                    const std::vector<double>& p_diffused, const std::vector<int>& neighbours,
                    const std::string& stage) {
  const Frame& f = ctx.frame.view();
  const size_t n = nodes.size();
  if (p_diffused.size() != 3 * n || neighbours.size() != 3 * n)
    throw std::logic_error("mgd DecideLines: 3 values per line expected");
  trace::TraceWriter& tr = ctx.trace;
  const bool full = tr.full_enabled();
  s.prev_line_p.assign(n, {-1.0, -1.0, -1.0});
  int64_t out = 0;
  for (size_t i = 0; i < n; ++i) {
    const std::string id = FrameStructure::LineId(f.index, static_cast<int>(i));
    const int64_t ml = i < f.structure.map_line_ids.size() ? f.structure.map_line_ids[i] : -1;
    double p_max = 0;
    for (size_t k = 0; k < 3; ++k) {
      const double p = p_diffused[3 * i + k];
      s.prev_line_p[i][k] = p;
      p_max = std::max(p_max, p);
      if (full) {  // the sample's 3-D point (camera frame): the diffusion is recomputable (issue 32)
        const bool has_X = nodes.has_X[i][k];
        const Eigen::Vector3d& X = nodes.X[i][k];
        tr.ProbabilityUpdate("mgd.diffuse", trace::EntityKind::kLineSample, id,
                             {{"sample", double(k)}, {"neighbours", double(neighbours[3 * i + k])},
                              {"map_line", double(ml)}, {"has_point", has_X ? 1.0 : 0.0}, {"x", has_X ? X.x() : 0.0},
                              {"y", has_X ? X.y() : 0.0}, {"z", has_X ? X.z() : 0.0}},
                             nodes.p_smooth[i][k], p);
      }
    }
    const double w = LineWeight(p_max, o);
    if (full) {  // the line's P: the largest of its samples (what the decision and the overlay use)
      double before = 0;
      for (size_t k = 0; k < 3; ++k) before = std::max(before, nodes.p_smooth[i][k]);
      tr.ProbabilityUpdate("mgd.line", trace::EntityKind::kLineSample, id,
                           {{"map_line", double(ml)}, {"weight", w}}, before, p_max);
    }
    ctx.frame.SetLineWeight(static_cast<int>(i), w);
    if (ml >= 0 && ctx.map.good_line(ml) != nullptr) ctx.frame.SetLineDynamicProbability(ml, p_max, stage);
    if (w <= 0) ++out;
    if (full)
      tr.Decision(stage, trace::EntityKind::kLineSample, id, w > 0, w > 0 ? "max_p<=tau_dyn" : "max_p>tau_dyn");
  }
  tr.FrameCount(stage, "lines_suppressed", out);
  return out;
}

}  // namespace dynref::mgd
