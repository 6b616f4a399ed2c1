// Local bundle adjustment: ORB-SLAM2 Optimizer::LocalBundleAdjustment (Mur-Artal & Tardos 2017,
// Sec. IV-B "local BA") with Ceres instead of g2o. Conventions in optim/optim.h.
// The caller chooses the keyframes (ORB-SLAM2: covisible keyframes free, keyframes that only
// observe local points fixed), points and observations; this function only optimises.
#include <ceres/ceres.h>

#include <cmath>
#include <limits>
#include <memory>

#include "core/error.h"
#include "optim/optim.h"
#include "optim/reprojection.h"
#include "optim/structure_residuals.h"
#include "trace/trace_writer.h"

namespace dynref::optim {

void LocalBAOptions::Check() const {
  const std::string where = "LocalBAOptions";
  if (iterations_robust < 0) throw InputError(where, "iterations_robust must be >= 0");
  if (iterations_refine < 0) throw InputError(where, "iterations_refine must be >= 0");
  if (!(chi2_mono > 0)) throw InputError(where, "chi2_mono must be > 0");
  if (!(chi2_stereo > 0)) throw InputError(where, "chi2_stereo must be > 0");
}

namespace {

// An edge of the BA graph: the shared per-observation model plus its keyframe and point.
struct BAEdge : EdgeModel {
  size_t kf = 0;     // index into keyframes
  size_t point = 0;  // index into points
};

// Gauge prior of line endpoints along their line (structure_residuals.h): 0.1 m, loose enough
// to be inert where the images constrain, tight enough to stop drift along the null space.
constexpr double kLineGaugeSigmaM = 0.1;

// A line or plane observation: its observation index, keyframe index and landmark index.
struct StructureEdge {
  size_t obs = 0, kf = 0, landmark = 0;
};

// chi2 of one edge at the current parameters (EdgeChi2 in reprojection.h; ORB-SLAM2:
// !e->isDepthPositive() => outlier).
double EdgeChi2(const Intrinsics& K, const std::vector<SE3>& T_cw,
                const std::vector<Eigen::Vector3d>& X_w, const BAEdge& edge,
                std::vector<double>* raw, double* weighted = nullptr) {
  return optim::EdgeChi2(K, T_cw[edge.kf], X_w[edge.point], edge, raw, weighted);
}

// Index of each id in input order; duplicates are bad input.
template <typename T>
std::map<int64_t, size_t> IndexById(const std::vector<T>& items, const std::string& what) {
  std::map<int64_t, size_t> index;
  for (size_t i = 0; i < items.size(); ++i) {
    if (!index.emplace(items[i].id, i).second) {
      throw InputError("LocalBundleAdjust",
                       "duplicate " + what + " id " + std::to_string(items[i].id));
    }
  }
  return index;
}

// State of one Ceres problem over all keyframes/points; edges can be excluded per phase.
class BAProblem {
 public:
  BAProblem(const Intrinsics& K, const std::vector<BAKeyFrame>& keyframes,
            const std::vector<BAPoint>& points, const std::vector<BAEdge>& edges,
            const LocalBAOptions& options, const LocalBAStructure& st, const std::vector<StructureEdge>& line_edges,
            const std::vector<StructureEdge>& plane_edges)
      : K_(K),
        keyframes_(keyframes),
        edges_(edges),
        st_(st),
        line_edges_(line_edges),
        plane_edges_(plane_edges),
        huber_mono_(std::sqrt(options.chi2_mono)),
        huber_stereo_(std::sqrt(options.chi2_stereo)),
        huber_line_(std::sqrt(st.options.LineChi2())),
        huber_plane_(std::sqrt(st.options.chi2_plane)) {
    // Every parameter block lives in ONE array, in this order: Ceres keeps the blocks of an
    // elimination group in a pointer-ordered set, so blocks of separately allocated arrays would
    // be ordered by heap address (different from run to run: the Schur complement sums in
    // another order, results differ in the last bits). One array: pointer order = index order.
    const size_t n_pose = keyframes.size() * 7, n_point = points.size() * 3, n_line = st.lines.size() * 6,
                 n_plane = st.planes.size();
    storage_.assign(n_pose + n_point + n_line + 4 * n_plane, 0.0);
    double* base = storage_.data();
    pose_params_ = {base, n_pose};
    point_params_ = {base + n_pose, n_point};
    line_params_ = {base + n_pose + n_point, n_line};
    plane_n_ = {base + n_pose + n_point + n_line, 3 * n_plane};
    plane_d_ = {base + n_pose + n_point + n_line + 3 * n_plane, n_plane};
    for (size_t k = 0; k < keyframes.size(); ++k)
      PoseToParams(keyframes[k].T_cw, &pose_params_[k * 7]);
    for (size_t p = 0; p < points.size(); ++p) {
      for (int c = 0; c < 3; ++c) point_params_[p * 3 + c] = points[p].X_w[c];
    }
    // One cost functor per edge, built once and shared by both phases' problems (as in
    // OptimizePose): a Problem that owns its functors needs one allocation and one std::map
    // ref-count entry per residual per phase; sharing saves 6-9 % of a call, bit-identical
    // (ref/optim/README.md).
    costs_.resize(edges.size());
    for (size_t i = 0; i < edges.size(); ++i) {
      const BAEdge& e = edges[i];
      const double s = std::sqrt(e.info);
      if (e.stereo) {
        costs_[i] = std::make_unique<BACost<3>>(K, e.obs, s);
      } else {
        costs_[i] = std::make_unique<BACost<2>>(K, e.obs, s);
      }
    }
    for (size_t k = 0; k < st.lines.size(); ++k)
      for (int c = 0; c < 3; ++c) line_params_[k * 6 + c] = st.lines[k].P_s[c], line_params_[k * 6 + 3 + c] = st.lines[k].P_e[c];
    for (size_t k = 0; k < st.planes.size(); ++k) {
      for (int c = 0; c < 3; ++c) plane_n_[k * 3 + c] = st.planes[k].n[c];
      plane_d_[k] = st.planes[k].d;
    }
    for (const BALine& L : st.lines)
      gauge_costs_.push_back(std::make_unique<LineGaugePrior>(L.P_s, L.P_e, kLineGaugeSigmaM));
    for (const StructureEdge& e : line_edges) {
      const BALineObservation& o = st.line_observations[e.obs];
      line_costs_.push_back(
          std::make_unique<LineBACost>(K, o.l, o.has_companion ? &o.l_companion : nullptr, o.weight, st.options));
    }
    for (const StructureEdge& e : plane_edges) {
      const BAPlaneObservation& o = st.plane_observations[e.obs];
      plane_costs_.push_back(std::make_unique<PlaneBACost>(o.n_obs, o.d_obs, o.weight, st.options));
    }
  }

  // Observation models at the current parameters (for chi2 / classification).
  LineObservation LineAt(const StructureEdge& e) const {
    const BALineObservation& o = st_.line_observations[e.obs];
    LineObservation m;
    const Eigen::Vector3d Ps(&line_params_[e.landmark * 6]), Pe(&line_params_[e.landmark * 6 + 3]);
    m.X_w = {Ps, 0.5 * (Ps + Pe), Pe};
    m.l = o.l, m.l_companion = o.l_companion, m.has_companion = o.has_companion, m.weight = o.weight;
    return m;
  }
  PlaneObservationResidual PlaneAt(const StructureEdge& e) const {
    const BAPlaneObservation& o = st_.plane_observations[e.obs];
    PlaneObservationResidual m;
    m.n_w = Eigen::Vector3d(&plane_n_[e.landmark * 3]);
    m.d_w = plane_d_[e.landmark];
    m.n_obs = o.n_obs, m.d_obs = o.d_obs, m.weight = o.weight;
    return m;
  }

  // Runs `iterations` LM iterations over the edges with active[i] != 0.
  void Solve(int iterations, bool robust, const std::vector<uint8_t>& active,
             const std::vector<uint8_t>& line_active, const std::vector<uint8_t>& plane_active) {
    if (iterations <= 0) return;
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    ceres::ParameterBlockOrdering* ordering = new ceres::ParameterBlockOrdering;
    std::vector<uint8_t> pose_added(keyframes_.size(), 0);
    std::vector<uint8_t> point_added(point_params_.size() / 3, 0);
    int added = 0;
    for (size_t i = 0; i < edges_.size(); ++i) {  // input order
      const BAEdge& e = edges_[i];
      if (!active[i] || !(e.info > 0)) continue;
      double* pose = &pose_params_[e.kf * 7];
      double* point = &point_params_[e.point * 3];
      if (!pose_added[e.kf]) {
        problem.AddParameterBlock(pose, 7, &manifold_);
        if (keyframes_[e.kf].fixed) problem.SetParameterBlockConstant(pose);
        ordering->AddElementToGroup(pose, 1);
        pose_added[e.kf] = 1;
      }
      if (!point_added[e.point]) {
        problem.AddParameterBlock(point, 3);
        ordering->AddElementToGroup(point, 0);  // points eliminated first (Schur complement)
        point_added[e.point] = 1;
      }
      ceres::LossFunction* loss = e.stereo ? &huber_stereo_ : &huber_mono_;
      problem.AddResidualBlock(costs_[i].get(), robust ? loss : nullptr, pose, point);
      ++added;
    }
    const auto add_pose = [&](size_t kf) {
      double* pose = &pose_params_[kf * 7];
      if (!pose_added[kf]) {
        problem.AddParameterBlock(pose, 7, &manifold_);
        if (keyframes_[kf].fixed) problem.SetParameterBlockConstant(pose);
        ordering->AddElementToGroup(pose, 1);
        pose_added[kf] = 1;
      }
      return pose;
    };
    std::vector<uint8_t> line_added(st_.lines.size(), 0), plane_added(st_.planes.size(), 0);
    for (size_t i = 0; i < line_edges_.size(); ++i) {
      const StructureEdge& e = line_edges_[i];
      if (!line_active[i] || !(st_.line_observations[e.obs].weight > 0)) continue;
      double* pose = add_pose(e.kf);
      double* line = &line_params_[e.landmark * 6];
      if (!line_added[e.landmark]) {
        problem.AddParameterBlock(line, 6);
        ordering->AddElementToGroup(line, 0);  // eliminated with the points
        problem.AddResidualBlock(gauge_costs_[e.landmark].get(), nullptr, line);
        line_added[e.landmark] = 1;
      }
      problem.AddResidualBlock(line_costs_[i].get(), robust ? &huber_line_ : nullptr, pose, line);
      ++added;
    }
    for (size_t i = 0; i < plane_edges_.size(); ++i) {
      const StructureEdge& e = plane_edges_[i];
      if (!plane_active[i] || !(st_.plane_observations[e.obs].weight > 0)) continue;
      double* pose = add_pose(e.kf);
      double* n = &plane_n_[e.landmark * 3];
      double* d = &plane_d_[e.landmark];
      if (!plane_added[e.landmark]) {
        problem.AddParameterBlock(n, 3, &sphere_);
        problem.AddParameterBlock(d, 1);
        ordering->AddElementToGroup(n, 1);  // two blocks of one residual: not both eliminable
        ordering->AddElementToGroup(d, 1);
        plane_added[e.landmark] = 1;
      }
      problem.AddResidualBlock(plane_costs_[i].get(), robust ? &huber_plane_ : nullptr, pose, n, d);
      ++added;
    }
    if (added == 0) {
      delete ordering;
      return;
    }
    ceres::Solver::Options opts;
    opts.minimizer_type = ceres::TRUST_REGION;
    opts.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    opts.linear_solver_type = ceres::DENSE_SCHUR;  // fixed solver choice (determinism)
    opts.linear_solver_ordering.reset(ordering);
    if (ordering->GroupSize(0) == 0) {  // planes only: nothing to eliminate
      opts.linear_solver_type = ceres::DENSE_QR;
      opts.linear_solver_ordering.reset();
    }
    opts.max_num_iterations = iterations;
    opts.num_threads = 1;
    opts.logging_type = ceres::SILENT;
    opts.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    ceres::Solve(opts, &problem, &summary);
  }

  std::vector<SE3> Poses() const {
    std::vector<SE3> T(keyframes_.size());
    for (size_t k = 0; k < keyframes_.size(); ++k) {
      // Fixed keyframes are returned bit-exactly as given (no quaternion round trip).
      T[k] = keyframes_[k].fixed ? keyframes_[k].T_cw : ParamsToPose(&pose_params_[k * 7]);
    }
    return T;
  }
  std::pair<Eigen::Vector3d, Eigen::Vector3d> Line(size_t k) const {
    return {Eigen::Vector3d(&line_params_[k * 6]), Eigen::Vector3d(&line_params_[k * 6 + 3])};
  }
  std::pair<Eigen::Vector3d, double> Plane(size_t k) const { return {Eigen::Vector3d(&plane_n_[k * 3]), plane_d_[k]}; }
  std::vector<Eigen::Vector3d> Points() const {
    std::vector<Eigen::Vector3d> X(point_params_.size() / 3);
    for (size_t p = 0; p < X.size(); ++p) {
      X[p] =
          Eigen::Vector3d(point_params_[p * 3], point_params_[p * 3 + 1], point_params_[p * 3 + 2]);
    }
    return X;
  }

 private:
  const Intrinsics& K_;
  const std::vector<BAKeyFrame>& keyframes_;
  const std::vector<BAEdge>& edges_;
  const LocalBAStructure& st_;
  const std::vector<StructureEdge>& line_edges_;
  const std::vector<StructureEdge>& plane_edges_;
  // Views into storage_ (see the constructor).
  struct Block {
    double* p = nullptr;
    size_t n = 0;
    double& operator[](size_t i) { return p[i]; }
    const double& operator[](size_t i) const { return p[i]; }
    size_t size() const { return n; }
  };
  std::vector<double> storage_;
  Block pose_params_;
  Block line_params_, plane_n_, plane_d_;
  ceres::SphereManifold<3> sphere_;
  Block point_params_;
  PoseManifold manifold_;
  ceres::HuberLoss huber_mono_;
  ceres::HuberLoss huber_stereo_;
  ceres::HuberLoss huber_line_, huber_plane_;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs_;  // per edge, both phases
  std::vector<std::unique_ptr<ceres::CostFunction>> line_costs_, plane_costs_;
  std::vector<std::unique_ptr<ceres::CostFunction>> gauge_costs_;  // per line (LineGaugePrior)
};

// Edges of the point observations; unknown ids and negative weights are bad input.
std::vector<BAEdge> LocalBaMakeEdges(const std::map<int64_t, size_t>& kf_index,
                                     const std::map<int64_t, size_t>& point_index,
                                     const std::vector<BAObservation>& observations, const LocalBAOptions& options) {
  std::vector<BAEdge> edges(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const BAObservation& o = observations[i];
    const auto kf = kf_index.find(o.kf_id);
    const auto pt = point_index.find(o.point_id);
    if (kf == kf_index.end() || pt == point_index.end()) {
      throw InputError("LocalBundleAdjust",
                       "observation " + std::to_string(i) + " refers to unknown keyframe/point id");
    }
    if (!(o.inv_sigma2 >= 0) || !(o.weight >= 0)) {
      throw InputError("LocalBundleAdjust",
                       "observation " + std::to_string(i) + ": inv_sigma2 and weight must be >= 0");
    }
    BAEdge& e = edges[i];
    e.kf = kf->second;
    e.point = pt->second;
    static_cast<EdgeModel&>(e) = MakeEdgeModel(o.uv, o.u_right, o.inv_sigma2, o.weight, options.chi2_mono,
                                               options.chi2_stereo, options.weighted_outlier_test);
  }
  return edges;
}

// Edges of one kind of structure observation (line or plane): keyframe and landmark indices.
template <class Observation, class LandmarkId>
std::vector<StructureEdge> LocalBaStructureEdgesOf(const std::vector<Observation>& observations,
                                                   const std::map<int64_t, size_t>& kf_index,
                                                   const std::map<int64_t, size_t>& landmark_index,
                                                   LandmarkId landmark_id, const std::string& kind) {
  std::vector<StructureEdge> edges(observations.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    const Observation& o = observations[i];
    const auto kf = kf_index.find(o.kf_id);
    const auto l = landmark_index.find(landmark_id(o));
    if (kf == kf_index.end() || l == landmark_index.end() || !(o.weight >= 0))
      throw InputError("LocalBundleAdjust", kind + " observation " + std::to_string(i) + ": unknown id or negative weight");
    edges[i] = {i, kf->second, l->second};
  }
  return edges;
}

// Edges of the line and plane observations.
void LocalBaMakeStructureEdges(const LocalBAStructure& st, const std::map<int64_t, size_t>& kf_index,
                               std::vector<StructureEdge>* line_edges, std::vector<StructureEdge>* plane_edges) {
  const std::map<int64_t, size_t> line_index = IndexById(st.lines, "line");
  const std::map<int64_t, size_t> plane_index = IndexById(st.planes, "plane");
  *line_edges = LocalBaStructureEdgesOf(st.line_observations, kf_index, line_index,
                                        [](const BALineObservation& o) { return o.line_id; }, "line");
  *plane_edges = LocalBaStructureEdgesOf(st.plane_observations, kf_index, plane_index,
                                         [](const BAPlaneObservation& o) { return o.plane_id; }, "plane");
}

// The terms of one LocalBundleAdjust call and their chi2 at given poses.
struct LocalBaTerms {
  const Intrinsics& K;
  const LocalBAStructure& st;
  const std::vector<BAEdge>& edges;
  const std::vector<StructureEdge>& line_edges;
  const std::vector<StructureEdge>& plane_edges;
  BAProblem& problem;
  double line_th = 0, plane_th = 0;
  bool log = false;
  double LineChi2At(const std::vector<SE3>& T, size_t i, std::vector<double>* raw, double* weighted) const {
    return LineChi2(K, T[line_edges[i].kf], problem.LineAt(line_edges[i]), st.options, raw, weighted);
  }
  double PlaneChi2At(const std::vector<SE3>& T, size_t i, std::vector<double>* raw, double* weighted) const {
    return PlaneChi2(T[plane_edges[i].kf], problem.PlaneAt(plane_edges[i]), st.options, raw, weighted);
  }
};

// Which terms take part in the current phase, and what the link / residual records need.
struct LocalBaPhaseState {
  std::vector<uint8_t> active, line_active, plane_active;
  std::vector<std::vector<double>> residual_start, line_start, plane_start;  // only when logging
  // Outlier-test chi2 after the robust phase (+inf: not in it), for the link records.
  std::vector<double> robust_chi2, line_robust_chi2, plane_robust_chi2;
};

LocalBaPhaseState LocalBaInitPhaseState(const LocalBaTerms& t) {
  const size_t n = t.edges.size(), nl = t.line_edges.size(), np = t.plane_edges.size();
  LocalBaPhaseState ps;
  ps.residual_start.resize(t.log ? n : 0);
  ps.line_start.resize(t.log ? nl : 0), ps.plane_start.resize(t.log ? np : 0);
  ps.line_active.assign(nl, 0), ps.plane_active.assign(np, 0);
  const double kInf = std::numeric_limits<double>::infinity();
  ps.robust_chi2.assign(t.log ? n : 0, kInf), ps.line_robust_chi2.assign(t.log ? nl : 0, kInf),
      ps.plane_robust_chi2.assign(t.log ? np : 0, kInf);
  ps.active.assign(n, 0);
  return ps;
}

// Only terms with a valid projection at the start enter the robust phase.
void LocalBaClassifyStart(const LocalBaTerms& t, LocalBaPhaseState* ps) {
  const std::vector<SE3> T = t.problem.Poses();
  const std::vector<Eigen::Vector3d> X = t.problem.Points();
  for (size_t i = 0; i < t.edges.size(); ++i) {
    const double c = EdgeChi2(t.K, T, X, t.edges[i], t.log ? &ps->residual_start[i] : nullptr);
    ps->active[i] = std::isfinite(c) ? 1 : 0;
  }
  for (size_t i = 0; i < t.line_edges.size(); ++i)
    ps->line_active[i] = std::isfinite(t.LineChi2At(T, i, t.log ? &ps->line_start[i] : nullptr, nullptr)) ? 1 : 0;
  for (size_t i = 0; i < t.plane_edges.size(); ++i)
    ps->plane_active[i] = std::isfinite(t.PlaneChi2At(T, i, t.log ? &ps->plane_start[i] : nullptr, nullptr)) ? 1 : 0;
}

// Outlier removal: chi2 > threshold or depth not positive (ORB-SLAM2 setLevel(1)).
void LocalBaRemoveOutliers(const LocalBaTerms& t, LocalBaPhaseState* ps) {
  const std::vector<SE3> T = t.problem.Poses();
  const std::vector<Eigen::Vector3d> X = t.problem.Points();
  for (size_t i = 0; i < t.edges.size(); ++i) {
    if (!ps->active[i]) continue;
    const double c = EdgeChi2(t.K, T, X, t.edges[i], nullptr);
    if (t.log) ps->robust_chi2[i] = c;
    ps->active[i] = c <= t.edges[i].threshold ? 1 : 0;
  }
  for (size_t i = 0; i < t.line_edges.size(); ++i) {
    if (!ps->line_active[i]) continue;
    const double c = t.LineChi2At(T, i, nullptr, nullptr);
    if (t.log) ps->line_robust_chi2[i] = c;
    ps->line_active[i] = c <= t.line_th ? 1 : 0;
  }
  for (size_t i = 0; i < t.plane_edges.size(); ++i) {
    if (!ps->plane_active[i]) continue;
    const double c = t.PlaneChi2At(T, i, nullptr, nullptr);
    if (t.log) ps->plane_robust_chi2[i] = c;
    ps->plane_active[i] = c <= t.plane_th ? 1 : 0;
  }
}

// Where the final classification writes its link and residual records (trace null: none).
struct LocalBaTraceSink {
  trace::TraceWriter* trace;
  const std::string& call_id;
  std::string link;
};

constexpr int kLocalBaFeature = 0, kLocalBaLineSample = 3, kLocalBaPlane = 4;  // trace::EntityKind

// Final point classification at the refined parameters (+ link / residual records).
void LocalBaClassifyPoints(const LocalBaTerms& t, const std::vector<BAObservation>& observations,
                           const LocalBaPhaseState& ps, const LocalBaTraceSink& sink, const std::vector<SE3>& T,
                           const std::vector<Eigen::Vector3d>& X, std::vector<double>* residual_end,
                           LocalBAResult* result) {
  const size_t n = t.edges.size();
  result->inlier.assign(n, 0);
  std::vector<double> chi2(n);
  for (size_t i = 0; i < n; ++i) {
    double weighted = 0;
    chi2[i] = EdgeChi2(t.K, T, X, t.edges[i], t.log ? residual_end : nullptr, &weighted);
    // Dropped edges stay outliers (g2o keeps their stale error above the threshold).
    result->inlier[i] = ps.active[i] && chi2[i] <= t.edges[i].threshold ? 1 : 0;
    result->num_inliers += result->inlier[i];
    if (t.log) {
      const BAObservation& o = observations[i];
      const std::string obs_id = "mp" + std::to_string(o.point_id) + "@kf" + std::to_string(o.kf_id);
      WriteResidualLink(*sink.trace, sink.link, kLocalBaFeature, obs_id, "feature", o.trace_feature,
                        {{"robust_chi2", ps.robust_chi2[i]}});
      sink.trace->Residual(sink.call_id, t.edges[i].stereo ? "rgbd3" : "mono2", obs_id,
                           ps.residual_start[i], *residual_end, o.inv_sigma2, o.weight,
                           HuberRho(weighted, t.edges[i].threshold), chi2[i], result->inlier[i] != 0);
    }
  }
  result->chi2 = chi2;
}

// Final line and plane classification (+ link / residual records), after the points.
void LocalBaClassifyStructure(const LocalBaTerms& t, const LocalBaPhaseState& ps, const LocalBaTraceSink& sink,
                              const std::vector<SE3>& T, std::vector<double>* residual_end, LocalBAResult* result) {
  const LocalBAStructure& st = t.st;
  result->line_inlier.assign(t.line_edges.size(), 0);
  result->plane_inlier.assign(t.plane_edges.size(), 0);
  for (size_t i = 0; i < t.line_edges.size(); ++i) {
    double weighted = 0;
    const double c = t.LineChi2At(T, i, t.log ? residual_end : nullptr, &weighted);
    result->line_inlier[i] = ps.line_active[i] && c <= t.line_th ? 1 : 0;
    if (t.log) {
      const BALineObservation& o = st.line_observations[i];
      const std::string obs_id = "ml" + std::to_string(o.line_id) + "@kf" + std::to_string(o.kf_id);
      WriteResidualLink(*sink.trace, sink.link, kLocalBaLineSample, obs_id, "line", o.trace_line,
                        {{"robust_chi2", ps.line_robust_chi2[i]}});
      sink.trace->Residual(sink.call_id, st.options.literal_line ? "line1" : "line4", obs_id, ps.line_start[i],
                           *residual_end, 1.0 / (st.options.line_sigma_px * st.options.line_sigma_px), o.weight,
                           HuberRho(weighted, t.line_th), c, result->line_inlier[i] != 0);
    }
  }
  for (size_t i = 0; i < t.plane_edges.size(); ++i) {
    double weighted = 0;
    const double c = t.PlaneChi2At(T, i, t.log ? residual_end : nullptr, &weighted);
    result->plane_inlier[i] = ps.plane_active[i] && c <= t.plane_th ? 1 : 0;
    if (t.log) {
      const BAPlaneObservation& o = st.plane_observations[i];
      const std::string obs_id = "mpl" + std::to_string(o.plane_id) + "@kf" + std::to_string(o.kf_id);
      WriteResidualLink(*sink.trace, sink.link, kLocalBaPlane, obs_id, "plane", o.trace_plane,
                        {{"robust_chi2", ps.plane_robust_chi2[i]}});
      sink.trace->Residual(sink.call_id, "plane3", obs_id, ps.plane_start[i], *residual_end,
                           1.0 / (st.options.plane_dist_sigma_m * st.options.plane_dist_sigma_m), o.weight,
                           HuberRho(weighted, t.plane_th), c, result->plane_inlier[i] != 0);
    }
  }
}

}  // namespace

LocalBAResult LocalBundleAdjust(const Intrinsics& K, const std::vector<BAKeyFrame>& keyframes,
                                const std::vector<BAPoint>& points,
                                const std::vector<BAObservation>& observations,
                                const LocalBAOptions& options, trace::TraceWriter* trace,
                                const std::string& call_id) {
  return LocalBundleAdjust(K, keyframes, points, observations, nullptr, options, trace, call_id);
}

LocalBAResult LocalBundleAdjust(const Intrinsics& K, const std::vector<BAKeyFrame>& keyframes,
                                const std::vector<BAPoint>& points,
                                const std::vector<BAObservation>& observations, const LocalBAStructure* structure,
                                const LocalBAOptions& options, trace::TraceWriter* trace,
                                const std::string& call_id) {
  options.Check();
  static const LocalBAStructure kNoStructure;
  const LocalBAStructure& st = structure != nullptr ? *structure : kNoStructure;
  st.options.Check();
  const std::map<int64_t, size_t> kf_index = IndexById(keyframes, "keyframe");
  const std::map<int64_t, size_t> point_index = IndexById(points, "point");
  const std::vector<BAEdge> edges = LocalBaMakeEdges(kf_index, point_index, observations, options);
  std::vector<StructureEdge> line_edges, plane_edges;
  LocalBaMakeStructureEdges(st, kf_index, &line_edges, &plane_edges);
  const bool log = trace != nullptr && trace->full_enabled();
  BAProblem problem(K, keyframes, points, edges, options, st, line_edges, plane_edges);
  const LocalBaTerms terms{K, st, edges, line_edges, plane_edges, problem, st.options.LineChi2(), st.options.chi2_plane, log};
  LocalBaPhaseState ps = LocalBaInitPhaseState(terms);
  const LocalBaTraceSink sink{trace, call_id, log ? LinkStage(call_id) : std::string()};

  LocalBaClassifyStart(terms, &ps);
  // Phase 1: Huber (ORB-SLAM2 optimize(5)).
  problem.Solve(options.iterations_robust, /*robust=*/true, ps.active, ps.line_active, ps.plane_active);
  LocalBaRemoveOutliers(terms, &ps);
  // Phase 2: no robust kernel, outliers excluded (ORB-SLAM2 optimize(10)).
  problem.Solve(options.iterations_refine, /*robust=*/false, ps.active, ps.line_active, ps.plane_active);

  LocalBAResult result;
  const std::vector<SE3> T = problem.Poses();
  const std::vector<Eigen::Vector3d> X = problem.Points();
  for (size_t k = 0; k < keyframes.size(); ++k) result.T_cw[keyframes[k].id] = T[k];
  for (size_t p = 0; p < points.size(); ++p) result.X_w[points[p].id] = X[p];
  std::vector<double> residual_end;
  LocalBaClassifyPoints(terms, observations, ps, sink, T, X, &residual_end, &result);
  for (size_t k = 0; k < st.lines.size(); ++k) result.line_P[st.lines[k].id] = problem.Line(k);
  for (size_t k = 0; k < st.planes.size(); ++k) result.plane[st.planes[k].id] = problem.Plane(k);
  LocalBaClassifyStructure(terms, ps, sink, T, &residual_end, &result);
  return result;
}

}  // namespace dynref::optim
