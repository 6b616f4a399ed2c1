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
            const LocalBAOptions& options)
      : K_(K),
        keyframes_(keyframes),
        edges_(edges),
        huber_mono_(std::sqrt(options.chi2_mono)),
        huber_stereo_(std::sqrt(options.chi2_stereo)) {
    pose_params_.resize(keyframes.size() * 7);
    for (size_t k = 0; k < keyframes.size(); ++k)
      PoseToParams(keyframes[k].T_cw, &pose_params_[k * 7]);
    point_params_.resize(points.size() * 3);
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
  }

  // Runs `iterations` LM iterations over the edges with active[i] != 0.
  void Solve(int iterations, bool robust, const std::vector<uint8_t>& active) {
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
    if (added == 0) {
      delete ordering;
      return;
    }
    ceres::Solver::Options opts;
    opts.minimizer_type = ceres::TRUST_REGION;
    opts.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    opts.linear_solver_type = ceres::DENSE_SCHUR;  // fixed solver choice (determinism)
    opts.linear_solver_ordering.reset(ordering);
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
  std::vector<double> pose_params_;
  std::vector<double> point_params_;
  PoseManifold manifold_;
  ceres::HuberLoss huber_mono_;
  ceres::HuberLoss huber_stereo_;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs_;  // per edge, both phases
};

}  // namespace

LocalBAResult LocalBundleAdjust(const Intrinsics& K, const std::vector<BAKeyFrame>& keyframes,
                                const std::vector<BAPoint>& points,
                                const std::vector<BAObservation>& observations,
                                const LocalBAOptions& options, trace::TraceWriter* trace,
                                const std::string& call_id) {
  options.Check();
  const std::map<int64_t, size_t> kf_index = IndexById(keyframes, "keyframe");
  const std::map<int64_t, size_t> point_index = IndexById(points, "point");
  const size_t n = observations.size();
  std::vector<BAEdge> edges(n);
  for (size_t i = 0; i < n; ++i) {
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

  const bool log = trace != nullptr && trace->full_enabled();
  std::vector<std::vector<double>> residual_start(log ? n : 0);
  BAProblem problem(K, keyframes, points, edges, options);

  // Only edges with a valid projection at the start enter the robust phase.
  std::vector<uint8_t> active(n, 0);
  {
    const std::vector<SE3> T = problem.Poses();
    const std::vector<Eigen::Vector3d> X = problem.Points();
    for (size_t i = 0; i < n; ++i) {
      const double c = EdgeChi2(K, T, X, edges[i], log ? &residual_start[i] : nullptr);
      active[i] = std::isfinite(c) ? 1 : 0;
    }
  }
  // Phase 1: Huber (ORB-SLAM2 optimize(5)).
  problem.Solve(options.iterations_robust, /*robust=*/true, active);
  // Outlier removal: chi2 > threshold or depth not positive (ORB-SLAM2 setLevel(1)).
  {
    const std::vector<SE3> T = problem.Poses();
    const std::vector<Eigen::Vector3d> X = problem.Points();
    for (size_t i = 0; i < n; ++i) {
      if (!active[i]) continue;
      active[i] = EdgeChi2(K, T, X, edges[i], nullptr) <= edges[i].threshold ? 1 : 0;
    }
  }
  // Phase 2: no robust kernel, outliers excluded (ORB-SLAM2 optimize(10)).
  problem.Solve(options.iterations_refine, /*robust=*/false, active);

  LocalBAResult result;
  const std::vector<SE3> T = problem.Poses();
  const std::vector<Eigen::Vector3d> X = problem.Points();
  for (size_t k = 0; k < keyframes.size(); ++k) result.T_cw[keyframes[k].id] = T[k];
  for (size_t p = 0; p < points.size(); ++p) result.X_w[points[p].id] = X[p];
  result.inlier.assign(n, 0);
  std::vector<double> chi2(n), residual_end;
  for (size_t i = 0; i < n; ++i) {
    double weighted = 0;
    chi2[i] = EdgeChi2(K, T, X, edges[i], log ? &residual_end : nullptr, &weighted);
    // Dropped edges stay outliers (g2o keeps their stale error above the threshold).
    result.inlier[i] = active[i] && chi2[i] <= edges[i].threshold ? 1 : 0;
    result.num_inliers += result.inlier[i];
    if (log) {
      const BAObservation& o = observations[i];
      trace->Residual(call_id, edges[i].stereo ? "rgbd3" : "mono2",
                      "mp" + std::to_string(o.point_id) + "@kf" + std::to_string(o.kf_id),
                      residual_start[i], residual_end, o.inv_sigma2, o.weight,
                      HuberRho(weighted, edges[i].threshold), chi2[i], result.inlier[i] != 0);
    }
  }
  result.chi2 = chi2;
  return result;
}

}  // namespace dynref::optim
