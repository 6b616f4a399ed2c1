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
  const size_t n_lines = st.lines.size(), n_planes = st.planes.size();
  // A zero-length segment has no line (l = 0) and a degenerate plane no normal: refused by name.
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
  const size_t n = observations.size();
  std::vector<EdgeModel> edges(n);
  for (size_t i = 0; i < n; ++i) {
    const PoseObservation& o = observations[i];
    if (!(o.inv_sigma2 >= 0) || !(o.weight >= 0)) {
      throw InputError("OptimizePose",
                       "observation " + o.obs_id + ": inv_sigma2 and weight must be >= 0");
    }
    edges[i] = MakeEdgeModel(o.uv, o.u_right, o.inv_sigma2, o.weight, options.chi2_mono,
                             options.chi2_stereo, options.weighted_outlier_test);
  }

  const bool log = trace != nullptr && trace->full_enabled();
  std::vector<std::vector<double>> residual_start(log ? n : 0);

  PoseOnlyResult result;
  result.T_cw = T_cw_init;
  result.inlier.assign(n, 0);
  std::vector<double> chi2(n, 0.0);
  // Initial classification: only points in front of the camera enter the first round
  // (ORB-SLAM2 adds every matched point; a point behind the camera has no valid projection).
  for (size_t i = 0; i < n; ++i) {
    chi2[i] =
        EdgeChi2(K, T_cw_init, observations[i].X_w, edges[i], log ? &residual_start[i] : nullptr);
    result.inlier[i] = std::isfinite(chi2[i]) ? 1 : 0;
  }

  const double line_th = st.options.LineChi2(), plane_th = st.options.chi2_plane;
  std::vector<std::vector<double>> line_start(log ? n_lines : 0), plane_start(log ? n_planes : 0);
  result.line_inlier.assign(n_lines, 0);
  result.plane_inlier.assign(n_planes, 0);
  std::vector<double> line_chi2(n_lines, 0.0), plane_chi2(n_planes, 0.0);
  for (size_t i = 0; i < n_lines; ++i) {
    line_chi2[i] = LineChi2(K, T_cw_init, st.lines[i], st.options, log ? &line_start[i] : nullptr, nullptr);
    result.line_inlier[i] = std::isfinite(line_chi2[i]) ? 1 : 0;
  }
  for (size_t i = 0; i < n_planes; ++i) {
    plane_chi2[i] = PlaneChi2(T_cw_init, st.planes[i], st.options, log ? &plane_start[i] : nullptr, nullptr);
    result.plane_inlier[i] = std::isfinite(plane_chi2[i]) ? 1 : 0;
  }

  double pose[7];
  PoseToParams(T_cw_init, pose);
  PoseManifold manifold;
  ceres::HuberLoss huber_mono(std::sqrt(options.chi2_mono));
  ceres::HuberLoss huber_stereo(std::sqrt(options.chi2_stereo));
  const ceres::Solver::Options solver_options = MakeSolverOptions(options.iterations);
  // One cost functor per observation, built once and shared by every round's problem.
  std::vector<std::unique_ptr<ceres::CostFunction>> costs(n);
  for (size_t i = 0; i < n; ++i) {
    const double s = std::sqrt(edges[i].info);
    if (edges[i].stereo) {
      costs[i] = std::make_unique<PoseOnlyCost<3>>(K, observations[i].X_w, edges[i].obs, s);
    } else {
      costs[i] = std::make_unique<PoseOnlyCost<2>>(K, observations[i].X_w, edges[i].obs, s);
    }
  }

  ceres::HuberLoss huber_line(std::sqrt(line_th));
  ceres::HuberLoss huber_plane(std::sqrt(plane_th));
  std::vector<std::unique_ptr<ceres::CostFunction>> line_costs(n_lines), plane_costs(n_planes);
  for (size_t i = 0; i < n_lines; ++i) line_costs[i] = std::make_unique<LinePoseCost>(K, st.lines[i], st.options);
  for (size_t i = 0; i < n_planes; ++i) plane_costs[i] = std::make_unique<PlanePoseCost>(st.planes[i], st.options);

  if (n + n_lines + n_planes >= 3) {  // ORB-SLAM2: nInitialCorrespondences < 3 => pose left unchanged
    for (int round = 0; round < options.rounds; ++round) {
      // ORB-SLAM2 drops the robust kernel after the third classification (level-2 edges).
      const bool robust = round < options.rounds - 1;
      // ORB-SLAM2 calls vSE3->setEstimate(pFrame->mTcw) inside the loop: every round starts from
      // the initial pose with the current inlier set.
      if (options.restart_each_round) PoseToParams(T_cw_init, pose);
      ceres::Problem::Options problem_options;
      problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      ceres::Problem problem(problem_options);
      problem.AddParameterBlock(pose, 7, &manifold);
      int active = 0;
      for (size_t i = 0; i < n; ++i) {                            // input order
        if (!result.inlier[i] || !(edges[i].info > 0)) continue;  // outlier or weight 0
        ceres::LossFunction* loss = edges[i].stereo ? &huber_stereo : &huber_mono;
        problem.AddResidualBlock(costs[i].get(), robust ? loss : nullptr, pose);
        ++active;
      }
      for (size_t i = 0; i < n_lines; ++i) {
        if (!result.line_inlier[i] || !(st.lines[i].weight > 0)) continue;
        problem.AddResidualBlock(line_costs[i].get(), robust ? &huber_line : nullptr, pose);
        ++active;
      }
      for (size_t i = 0; i < n_planes; ++i) {
        if (!result.plane_inlier[i] || !(st.planes[i].weight > 0)) continue;
        problem.AddResidualBlock(plane_costs[i].get(), robust ? &huber_plane : nullptr, pose);
        ++active;
      }
      if (active == 0) break;
      ceres::Solver::Summary summary;
      ceres::Solve(solver_options, &problem, &summary);
      ++result.rounds_run;
      const SE3 T_cw = ParamsToPose(pose);
      // Re-classify every observation, including the current outliers (they can come back).
      int weighted_inliers = 0;
      for (size_t i = 0; i < n; ++i) {
        chi2[i] = EdgeChi2(K, T_cw, observations[i].X_w, edges[i], nullptr);
        result.inlier[i] = chi2[i] <= edges[i].threshold ? 1 : 0;
        if (result.inlier[i] && edges[i].info > 0) ++weighted_inliers;
      }
      for (size_t i = 0; i < n_lines; ++i) {
        line_chi2[i] = LineChi2(K, T_cw, st.lines[i], st.options, nullptr, nullptr);
        result.line_inlier[i] = line_chi2[i] <= line_th ? 1 : 0;
        if (result.line_inlier[i] && st.lines[i].weight > 0) ++weighted_inliers;
      }
      for (size_t i = 0; i < n_planes; ++i) {
        plane_chi2[i] = PlaneChi2(T_cw, st.planes[i], st.options, nullptr, nullptr);
        result.plane_inlier[i] = plane_chi2[i] <= plane_th ? 1 : 0;
        if (result.plane_inlier[i] && st.planes[i].weight > 0) ++weighted_inliers;
      }
      result.T_cw = T_cw;
      if (weighted_inliers < options.min_edges) break;
    }
  }

  if (result.rounds_run == 0) {  // nothing optimised: classify at the initial pose
    for (size_t i = 0; i < n; ++i) result.inlier[i] = chi2[i] <= edges[i].threshold ? 1 : 0;
    for (size_t i = 0; i < n_lines; ++i) result.line_inlier[i] = line_chi2[i] <= line_th ? 1 : 0;
    for (size_t i = 0; i < n_planes; ++i) result.plane_inlier[i] = plane_chi2[i] <= plane_th ? 1 : 0;
  }
  result.num_inliers = 0;
  for (size_t i = 0; i < n; ++i) result.num_inliers += result.inlier[i];
  for (uint8_t f : result.line_inlier) result.line_inliers += f;
  for (uint8_t f : result.plane_inlier) result.plane_inliers += f;
  result.chi2 = chi2;  // computed at result.T_cw (last classification or the initial pose)

  if (log) {
    std::vector<double> residual_end;
    const std::string link = LinkStage(call_id);
    constexpr int kFeature = 0, kLineSample = 3, kPlane = 4;  // trace::EntityKind
    for (size_t i = 0; i < n; ++i) {
      double weighted = 0;
      const double c = EdgeChi2(K, result.T_cw, observations[i].X_w, edges[i], &residual_end, &weighted);
      const Eigen::Vector3d& X = observations[i].X_w;
      WriteResidualLink(*trace, link, kFeature, observations[i].obs_id, "feature", observations[i].trace_feature,
                        {{"x", X.x()}, {"y", X.y()}, {"z", X.z()}});
      trace->Residual(call_id, edges[i].stereo ? "rgbd3" : "mono2", observations[i].obs_id,
                      residual_start[i], residual_end, observations[i].inv_sigma2,
                      observations[i].weight, HuberRho(weighted, edges[i].threshold), c,
                      result.inlier[i] != 0);
    }
    // Lines: information = 1 / sigma_l^2; planes: 1 / sigma_d^2 (the angle rows use 1 / sigma_a^2).
    for (size_t i = 0; i < n_lines; ++i) {
      double weighted = 0;
      const double c = LineChi2(K, result.T_cw, st.lines[i], st.options, &residual_end, &weighted);
      WriteResidualLink(*trace, link, kLineSample, st.lines[i].obs_id, "line", st.lines[i].trace_line, {});
      trace->Residual(call_id, st.options.literal_line ? "line1" : "line4", st.lines[i].obs_id, line_start[i],
                      residual_end, 1.0 / (st.options.line_sigma_px * st.options.line_sigma_px), st.lines[i].weight,
                      HuberRho(weighted, line_th), c, result.line_inlier[i] != 0);
    }
    for (size_t i = 0; i < n_planes; ++i) {
      double weighted = 0;
      const double c = PlaneChi2(result.T_cw, st.planes[i], st.options, &residual_end, &weighted);
      WriteResidualLink(*trace, link, kPlane, st.planes[i].obs_id, "plane", st.planes[i].trace_plane, {});
      trace->Residual(call_id, "plane3", st.planes[i].obs_id, plane_start[i], residual_end,
                      1.0 / (st.options.plane_dist_sigma_m * st.options.plane_dist_sigma_m), st.planes[i].weight,
                      HuberRho(weighted, plane_th), c, result.plane_inlier[i] != 0);
    }
  }
  return result;
}

}  // namespace dynref::optim
