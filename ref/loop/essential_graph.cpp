// The essential-graph pose optimisation; see essential_graph.h.
#include "loop/essential_graph.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Geometry>
#include <array>

#include "core/error.h"

namespace dynref::loop {
namespace {

// Ceres quaternion (w, x, y, z) + translation of T_cw.
struct PoseBlock {
  std::array<double, 4> q{};
  std::array<double, 3> t{};
};

PoseBlock ToBlock(const SE3& T) {
  const Eigen::Quaterniond q(T.linear());
  PoseBlock b;
  b.q = {q.w(), q.x(), q.y(), q.z()};
  b.t = {T.translation().x(), T.translation().y(), T.translation().z()};
  return b;
}

SE3 FromBlock(const PoseBlock& b) {
  Eigen::Quaterniond q(b.q[0], b.q[1], b.q[2], b.q[3]);
  q.normalize();
  SE3 T = SE3::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(b.t[0], b.t[1], b.t[2]);
  return T;
}

struct EdgeCost {
  std::array<double, 4> q_ji;
  std::array<double, 3> t_ji;
  template <typename T>
  bool operator()(const T* qi, const T* ti, const T* qj, const T* tj, T* r) const {
    const T qj_conj[4] = {qj[0], -qj[1], -qj[2], -qj[3]};
    T q_a[4];
    ceres::QuaternionProduct(qi, qj_conj, q_a);  // R_i R_j^T
    T rt[3];
    ceres::UnitQuaternionRotatePoint(q_a, tj, rt);
    const T t_a[3] = {ti[0] - rt[0], ti[1] - rt[1], ti[2] - rt[2]};
    const T qm[4] = {T(q_ji[0]), T(q_ji[1]), T(q_ji[2]), T(q_ji[3])};
    T q_e[4];
    ceres::QuaternionProduct(qm, q_a, q_e);
    T rt2[3];
    ceres::UnitQuaternionRotatePoint(qm, t_a, rt2);
    ceres::QuaternionToAngleAxis(q_e, r);
    for (int k = 0; k < 3; ++k) r[3 + k] = rt2[k] + T(t_ji[k]);
    return true;
  }
};

double SquaredNorm(const std::vector<double>& r) {
  double s = 0;
  for (double v : r) s += v * v;
  return s;
}

}  // namespace

std::vector<double> PoseGraphResidual(const PoseGraphEdge& e, const SE3& T_iw, const SE3& T_jw) {
  const SE3 E = e.T_ji * T_iw * T_jw.inverse();
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(E.linear()).normalized());
  const Eigen::Vector3d w = aa.angle() * aa.axis();
  return {w.x(), w.y(), w.z(), E.translation().x(), E.translation().y(), E.translation().z()};
}

PoseGraphResult OptimizePoseGraph(const std::map<int64_t, SE3>& T_cw, const std::set<int64_t>& fixed,
                                  const std::vector<PoseGraphEdge>& edges, int iterations, trace::TraceWriter* trace,
                                  const std::string& call_id) {
  std::map<int64_t, PoseBlock> blocks;
  for (const auto& [id, T] : T_cw) blocks[id] = ToBlock(T);
  std::vector<std::vector<double>> start;
  PoseGraphResult out;
  for (const PoseGraphEdge& e : edges) {
    if (!T_cw.count(e.i) || !T_cw.count(e.j))
      throw InputError("essential graph", "edge kf" + std::to_string(e.i) + "-kf" + std::to_string(e.j) + " names an unknown keyframe");
    start.push_back(PoseGraphResidual(e, T_cw.at(e.i), T_cw.at(e.j)));
    out.chi2_start += SquaredNorm(start.back());
  }
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges) {
    const Eigen::Quaterniond q(e.T_ji.linear());
    auto* cost = new ceres::AutoDiffCostFunction<EdgeCost, 6, 4, 3, 4, 3>(
        new EdgeCost{{q.w(), q.x(), q.y(), q.z()}, {e.T_ji.translation().x(), e.T_ji.translation().y(), e.T_ji.translation().z()}});
    PoseBlock& bi = blocks.at(e.i);
    PoseBlock& bj = blocks.at(e.j);
    problem.AddResidualBlock(cost, nullptr, bi.q.data(), bi.t.data(), bj.q.data(), bj.t.data());
  }
  for (auto& [id, b] : blocks) {
    if (!problem.HasParameterBlock(b.q.data())) continue;
    problem.SetManifold(b.q.data(), new ceres::QuaternionManifold);
    if (fixed.count(id)) {
      problem.SetParameterBlockConstant(b.q.data());
      problem.SetParameterBlockConstant(b.t.data());
    }
  }
  if (!edges.empty() && iterations > 0) {
    ceres::Solver::Options options;
    options.num_threads = 1;
    options.max_num_iterations = iterations;
    options.minimizer_type = ceres::TRUST_REGION;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    out.iterations = static_cast<int>(summary.iterations.size());
  }
  for (const auto& [id, b] : blocks) out.T_cw[id] = FromBlock(b);
  for (size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    const std::vector<double> end = PoseGraphResidual(e, out.T_cw.at(e.i), out.T_cw.at(e.j));
    const double chi2 = SquaredNorm(end);
    out.chi2_end += chi2;
    if (trace != nullptr && trace->full_enabled())
      trace->Residual(call_id, "se3edge6", "kf" + std::to_string(e.i) + "-kf" + std::to_string(e.j), start[k], end, 1.0,
                      1.0, chi2, chi2, true);
  }
  return out;
}

}  // namespace dynref::loop
