// Pose-only optimisation: ORB-SLAM2 Optimizer::PoseOptimization (Mur-Artal & Tardos 2017,
// Sec. IV-B "motion-only BA") with Ceres instead of g2o. Conventions in optim/optim.h.
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

void PoseOnlyOptions::Check() const {
  const std::string where = "PoseOnlyOptions";
  if (rounds < 1) throw InputError(where, "rounds must be >= 1");
  if (iterations < 1) throw InputError(where, "iterations must be >= 1");
  if (!(chi2_mono > 0)) throw InputError(where, "chi2_mono must be > 0");
  if (!(chi2_stereo > 0)) throw InputError(where, "chi2_stereo must be > 0");
  if (min_edges < 0) throw InputError(where, "min_edges must be >= 0");
}

namespace {

ceres::Solver::Options MakeSolverOptions(int iterations) {
  ceres::Solver::Options opts;
  opts.minimizer_type = ceres::TRUST_REGION;
  opts.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  opts.linear_solver_type = ceres::DENSE_QR;  // 6 unknowns; fixed solver choice (determinism)
  opts.max_num_iterations = iterations;
  opts.num_threads = 1;
  opts.logging_type = ceres::SILENT;
  opts.minimizer_progress_to_stdout = false;
  return opts;
}

// A zero-length segment has no line (l = 0) and a degenerate plane no normal: refused by name.
void PoseOptCheckStructure(const PoseStructure& st) {
  const auto unit = [](const Eigen::Vector2d& v) { return std::fabs(v.norm() - 1.0) < 1e-6; };
  for (const LineObservation& o : st.lines) {
    if (!(o.weight >= 0)) throw InputError("OptimizePose", "line observation " + o.obs_id + ": weight must be >= 0");
    if (!unit(o.l.head<2>()) || (o.has_companion && !unit(o.l_companion.head<2>())))
      throw InputError("OptimizePose", "line observation " + o.obs_id + ": the line is not normalised (zero-length segment?)");
  }
  for (const PlaneObservationResidual& o : st.planes) {
    if (!(o.weight >= 0)) throw InputError("OptimizePose", "plane observation " + o.obs_id + ": weight must be >= 0");
    if (std::fabs(o.n_w.norm() - 1.0) > 1e-6 || std::fabs(o.n_obs.norm() - 1.0) > 1e-6)
      throw InputError("OptimizePose", "plane observation " + o.obs_id + ": normal is not a unit vector");
  }
}

std::vector<EdgeModel> PoseOptMakeEdges(const std::vector<PoseObservation>& observations,
                                        const PoseOnlyOptions& options) {
  std::vector<EdgeModel> edges(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const PoseObservation& o = observations[i];
    if (!(o.inv_sigma2 >= 0) || !(o.weight >= 0)) {
      throw InputError("OptimizePose",
                       "observation " + o.obs_id + ": inv_sigma2 and weight must be >= 0");
    }
    edges[i] = MakeEdgeModel(o.uv, o.u_right, o.inv_sigma2, o.weight, options.chi2_mono,
                             options.chi2_stereo, options.weighted_outlier_test);
  }
  return edges;
}

// One OptimizePose call: its inputs, per-term edge models and the current chi2 of every term.
struct PoseOptState {
  const Intrinsics& K;
  const std::vector<PoseObservation>& observations;
  const PoseStructure& st;
  const PoseOnlyOptions& options;
  size_t n = 0, n_lines = 0, n_planes = 0;
  bool log = false;
  double line_th = 0, plane_th = 0;
  std::vector<EdgeModel> edges{};
  std::vector<double> chi2{}, line_chi2{}, plane_chi2{};
  std::vector<std::vector<double>> residual_start{}, line_start{}, plane_start{};  // only when logging
};

// Initial classification: only terms in front of the camera enter the first round
// (ORB-SLAM2 adds every matched point; a point behind the camera has no valid projection).
void PoseOptClassifyInitial(const SE3& T_cw_init, PoseOptState* s, PoseOnlyResult* result) {
  result->inlier.assign(s->n, 0);
  s->chi2.assign(s->n, 0.0);
  for (size_t i = 0; i < s->n; ++i) {
    s->chi2[i] = EdgeChi2(s->K, T_cw_init, s->observations[i].X_w, s->edges[i],
                          s->log ? &s->residual_start[i] : nullptr);
    result->inlier[i] = std::isfinite(s->chi2[i]) ? 1 : 0;
  }
  result->line_inlier.assign(s->n_lines, 0);
  result->plane_inlier.assign(s->n_planes, 0);
  s->line_chi2.assign(s->n_lines, 0.0);
  s->plane_chi2.assign(s->n_planes, 0.0);
  for (size_t i = 0; i < s->n_lines; ++i) {
    s->line_chi2[i] = LineChi2(s->K, T_cw_init, s->st.lines[i], s->st.options, s->log ? &s->line_start[i] : nullptr, nullptr);
    result->line_inlier[i] = std::isfinite(s->line_chi2[i]) ? 1 : 0;
  }
  for (size_t i = 0; i < s->n_planes; ++i) {
    s->plane_chi2[i] = PlaneChi2(T_cw_init, s->st.planes[i], s->st.options, s->log ? &s->plane_start[i] : nullptr, nullptr);
    result->plane_inlier[i] = std::isfinite(s->plane_chi2[i]) ? 1 : 0;
  }
}

// One cost functor per term and the robust kernels, built once and shared by every round's problem.
struct PoseOptCosts {
  explicit PoseOptCosts(const PoseOptState& s)
      : huber_mono(std::sqrt(s.options.chi2_mono)),
        huber_stereo(std::sqrt(s.options.chi2_stereo)),
        huber_line(std::sqrt(s.line_th)),
        huber_plane(std::sqrt(s.plane_th)),
        costs(s.n),
        line_costs(s.n_lines),
        plane_costs(s.n_planes) {
    for (size_t i = 0; i < s.n; ++i) {
      const double sq = std::sqrt(s.edges[i].info);
      if (s.edges[i].stereo) {
        costs[i] = std::make_unique<PoseOnlyCost<3>>(s.K, s.observations[i].X_w, s.edges[i].obs, sq);
      } else {
        costs[i] = std::make_unique<PoseOnlyCost<2>>(s.K, s.observations[i].X_w, s.edges[i].obs, sq);
      }
    }
    for (size_t i = 0; i < s.n_lines; ++i) line_costs[i] = std::make_unique<LinePoseCost>(s.K, s.st.lines[i], s.st.options);
    for (size_t i = 0; i < s.n_planes; ++i) plane_costs[i] = std::make_unique<PlanePoseCost>(s.st.planes[i], s.st.options);
  }
  ceres::HuberLoss huber_mono, huber_stereo, huber_line, huber_plane;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs, line_costs, plane_costs;
};

// Adds the current inliers with non-zero weight (input order); returns how many were added.
int PoseOptAddInliers(const PoseOptState& s, PoseOptCosts& c, const PoseOnlyResult& result, bool robust,
                      double* pose, ceres::Problem* problem) {
  int active = 0;
  for (size_t i = 0; i < s.n; ++i) {                          // input order
    if (!result.inlier[i] || !(s.edges[i].info > 0)) continue;  // outlier or weight 0
    ceres::LossFunction* loss = s.edges[i].stereo ? &c.huber_stereo : &c.huber_mono;
    problem->AddResidualBlock(c.costs[i].get(), robust ? loss : nullptr, pose);
    ++active;
  }
  for (size_t i = 0; i < s.n_lines; ++i) {
    if (!result.line_inlier[i] || !(s.st.lines[i].weight > 0)) continue;
    problem->AddResidualBlock(c.line_costs[i].get(), robust ? &c.huber_line : nullptr, pose);
    ++active;
  }
  for (size_t i = 0; i < s.n_planes; ++i) {
    if (!result.plane_inlier[i] || !(s.st.planes[i].weight > 0)) continue;
    problem->AddResidualBlock(c.plane_costs[i].get(), robust ? &c.huber_plane : nullptr, pose);
    ++active;
  }
  return active;
}

// Re-classify every term at T_cw, including the current outliers (they can come back);
// returns the number of weighted inliers.
int PoseOptReclassify(const SE3& T_cw, PoseOptState* s, PoseOnlyResult* result) {
  int weighted_inliers = 0;
  for (size_t i = 0; i < s->n; ++i) {
    s->chi2[i] = EdgeChi2(s->K, T_cw, s->observations[i].X_w, s->edges[i], nullptr);
    result->inlier[i] = s->chi2[i] <= s->edges[i].threshold ? 1 : 0;
    if (result->inlier[i] && s->edges[i].info > 0) ++weighted_inliers;
  }
  for (size_t i = 0; i < s->n_lines; ++i) {
    s->line_chi2[i] = LineChi2(s->K, T_cw, s->st.lines[i], s->st.options, nullptr, nullptr);
    result->line_inlier[i] = s->line_chi2[i] <= s->line_th ? 1 : 0;
    if (result->line_inlier[i] && s->st.lines[i].weight > 0) ++weighted_inliers;
  }
  for (size_t i = 0; i < s->n_planes; ++i) {
    s->plane_chi2[i] = PlaneChi2(T_cw, s->st.planes[i], s->st.options, nullptr, nullptr);
    result->plane_inlier[i] = s->plane_chi2[i] <= s->plane_th ? 1 : 0;
    if (result->plane_inlier[i] && s->st.planes[i].weight > 0) ++weighted_inliers;
  }
  return weighted_inliers;
}

// The optimise / re-classify rounds of ORB-SLAM2 PoseOptimization.
void PoseOptRunRounds(const SE3& T_cw_init, PoseOptState* s, PoseOnlyResult* result) {
  double pose[7];
  PoseToParams(T_cw_init, pose);
  PoseManifold manifold;
  const ceres::Solver::Options solver_options = MakeSolverOptions(s->options.iterations);
  PoseOptCosts costs(*s);
  if (s->n + s->n_lines + s->n_planes < 3) return;  // ORB-SLAM2: nInitialCorrespondences < 3 => pose left unchanged
  for (int round = 0; round < s->options.rounds; ++round) {
    // ORB-SLAM2 drops the robust kernel after the third classification (level-2 edges).
    const bool robust = round < s->options.rounds - 1;
    // ORB-SLAM2 calls vSE3->setEstimate(pFrame->mTcw) inside the loop: every round starts from
    // the initial pose with the current inlier set.
    if (s->options.restart_each_round) PoseToParams(T_cw_init, pose);
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    problem.AddParameterBlock(pose, 7, &manifold);
    if (PoseOptAddInliers(*s, costs, *result, robust, pose, &problem) == 0) break;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    ++result->rounds_run;
    const SE3 T_cw = ParamsToPose(pose);
    const int weighted_inliers = PoseOptReclassify(T_cw, s, result);
    result->T_cw = T_cw;
    if (weighted_inliers < s->options.min_edges) break;
  }
}

void PoseOptFinishClassification(const PoseOptState& s, PoseOnlyResult* result) {
  if (result->rounds_run == 0) {  // nothing optimised: classify at the initial pose
    for (size_t i = 0; i < s.n; ++i) result->inlier[i] = s.chi2[i] <= s.edges[i].threshold ? 1 : 0;
    for (size_t i = 0; i < s.n_lines; ++i) result->line_inlier[i] = s.line_chi2[i] <= s.line_th ? 1 : 0;
    for (size_t i = 0; i < s.n_planes; ++i) result->plane_inlier[i] = s.plane_chi2[i] <= s.plane_th ? 1 : 0;
  }
  result->num_inliers = 0;
  for (size_t i = 0; i < s.n; ++i) result->num_inliers += result->inlier[i];
  for (uint8_t f : result->line_inlier) result->line_inliers += f;
  for (uint8_t f : result->plane_inlier) result->plane_inliers += f;
  result->chi2 = s.chi2;  // computed at result.T_cw (last classification or the initial pose)
}

void PoseOptTraceResiduals(const PoseOptState& s, const PoseOnlyResult& result, trace::TraceWriter* trace,
                           const std::string& call_id) {
  std::vector<double> residual_end;
  const std::string link = LinkStage(call_id);
  constexpr int kFeature = 0, kLineSample = 3, kPlane = 4;  // trace::EntityKind
  const std::vector<PoseObservation>& obs = s.observations;
  for (size_t i = 0; i < s.n; ++i) {
    double weighted = 0;
    const double c = EdgeChi2(s.K, result.T_cw, obs[i].X_w, s.edges[i], &residual_end, &weighted);
    const Eigen::Vector3d& X = obs[i].X_w;
    WriteResidualLink(*trace, link, kFeature, obs[i].obs_id, "feature", obs[i].trace_feature,
                      {{"x", X.x()}, {"y", X.y()}, {"z", X.z()}});
    trace->Residual(call_id, s.edges[i].stereo ? "rgbd3" : "mono2", obs[i].obs_id, s.residual_start[i], residual_end,
                    obs[i].inv_sigma2, obs[i].weight, HuberRho(weighted, s.edges[i].threshold), c,
                    result.inlier[i] != 0);
  }
  // Lines: information = 1 / sigma_l^2; planes: 1 / sigma_d^2 (the angle rows use 1 / sigma_a^2).
  const PoseStructure& st = s.st;
  for (size_t i = 0; i < s.n_lines; ++i) {
    double weighted = 0;
    const double c = LineChi2(s.K, result.T_cw, st.lines[i], st.options, &residual_end, &weighted);
    WriteResidualLink(*trace, link, kLineSample, st.lines[i].obs_id, "line", st.lines[i].trace_line, {});
    trace->Residual(call_id, st.options.literal_line ? "line1" : "line4", st.lines[i].obs_id, s.line_start[i],
                    residual_end, 1.0 / (st.options.line_sigma_px * st.options.line_sigma_px), st.lines[i].weight,
                    HuberRho(weighted, s.line_th), c, result.line_inlier[i] != 0);
  }
  for (size_t i = 0; i < s.n_planes; ++i) {
    double weighted = 0;
    const double c = PlaneChi2(result.T_cw, st.planes[i], st.options, &residual_end, &weighted);
    WriteResidualLink(*trace, link, kPlane, st.planes[i].obs_id, "plane", st.planes[i].trace_plane, {});
    trace->Residual(call_id, "plane3", st.planes[i].obs_id, s.plane_start[i], residual_end,
                    1.0 / (st.options.plane_dist_sigma_m * st.options.plane_dist_sigma_m), st.planes[i].weight,
                    HuberRho(weighted, s.plane_th), c, result.plane_inlier[i] != 0);
  }
}

}  // namespace

PoseOnlyResult OptimizePose(const Intrinsics& K, const SE3& T_cw_init,
                            const std::vector<PoseObservation>& observations,
                            const PoseOnlyOptions& options, trace::TraceWriter* trace,
                            const std::string& call_id) {
  return OptimizePose(K, T_cw_init, observations, nullptr, options, trace, call_id);
}

PoseOnlyResult OptimizePose(const Intrinsics& K, const SE3& T_cw_init,
                            const std::vector<PoseObservation>& observations, const PoseStructure* structure,
                            const PoseOnlyOptions& options, trace::TraceWriter* trace,
                            const std::string& call_id) {
  options.Check();
  static const PoseStructure kNoStructure;
  const PoseStructure& st = structure != nullptr ? *structure : kNoStructure;
  st.options.Check();
  PoseOptCheckStructure(st);
  PoseOptState s{K, observations, st, options};
  s.n = observations.size(), s.n_lines = st.lines.size(), s.n_planes = st.planes.size();
  s.edges = PoseOptMakeEdges(observations, options);
  s.log = trace != nullptr && trace->full_enabled();
  s.residual_start.resize(s.log ? s.n : 0);
  s.line_th = st.options.LineChi2(), s.plane_th = st.options.chi2_plane;
  s.line_start.resize(s.log ? s.n_lines : 0), s.plane_start.resize(s.log ? s.n_planes : 0);

  PoseOnlyResult result;
  result.T_cw = T_cw_init;
  PoseOptClassifyInitial(T_cw_init, &s, &result);
  PoseOptRunRounds(T_cw_init, &s, &result);
  PoseOptFinishClassification(s, &result);
  if (s.log) PoseOptTraceResiduals(s, result, trace, call_id);
  return result;
}

}  // namespace dynref::optim
