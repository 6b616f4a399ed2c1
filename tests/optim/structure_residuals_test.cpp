// Line and plane residuals (issue 13): analytic Jacobians against central differences through
// the manifolds, hand-computed residual values (a flipped sign fails), and pose-only / local BA
// problems solved from lines and planes alone.
// Ceres (and its glog CHECK) first: catch.hpp's CHECK must be the one the tests use.
#include "optim/reprojection.h"
#include "optim/structure_residuals.h"
#include "optim/synthetic_problem.h"

#include <catch2/catch.hpp>

#include <cmath>

#include "core/rng.h"

using namespace dynref;
using namespace dynref::optim;

namespace {

using MatrixXdRow = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

SE3 StructurePose(Rng& rng, double scale = 0.5) {
  Eigen::Matrix<double, 6, 1> xi;
  for (int k = 0; k < 6; ++k) xi[k] = rng.Uniform(-scale, scale);
  return ExpSE3(xi);
}

// Block b of `cost` is checked in its tangent space: `manifolds[b]` (nullptr = Euclidean).
void CheckJacobians(const ceres::CostFunction& cost, std::vector<std::vector<double>> blocks,
                    const std::vector<const ceres::Manifold*>& manifolds) {
  const int nr = cost.num_residuals();
  const size_t nb = blocks.size();
  std::vector<double*> params;
  for (auto& b : blocks) params.push_back(b.data());
  std::vector<MatrixXdRow> J(nb);
  std::vector<double*> jac(nb);
  for (size_t b = 0; b < nb; ++b) {
    J[b].resize(nr, static_cast<int>(blocks[b].size()));
    jac[b] = J[b].data();
  }
  std::vector<double> e0(static_cast<size_t>(nr));
  REQUIRE(cost.Evaluate(params.data(), e0.data(), jac.data()));
  const double h = 1e-6;
  for (size_t b = 0; b < nb; ++b) {
    const int amb = static_cast<int>(blocks[b].size());
    const ceres::Manifold* m = manifolds[b];
    const int tan = m != nullptr ? m->TangentSize() : amb;
    MatrixXdRow plus(amb, tan);
    if (m != nullptr) REQUIRE(m->PlusJacobian(blocks[b].data(), plus.data()));
    else plus.setIdentity();
    const Eigen::MatrixXd Jt = J[b] * plus;
    for (int k = 0; k < tan; ++k) {
      std::vector<double> delta(static_cast<size_t>(tan), 0.0), xp(static_cast<size_t>(amb)), xm(static_cast<size_t>(amb));
      delta[static_cast<size_t>(k)] = h;
      if (m != nullptr) m->Plus(blocks[b].data(), delta.data(), xp.data());
      else for (int c = 0; c < amb; ++c) xp[static_cast<size_t>(c)] = blocks[b][static_cast<size_t>(c)] + delta[static_cast<size_t>(c)];
      delta[static_cast<size_t>(k)] = -h;
      if (m != nullptr) m->Plus(blocks[b].data(), delta.data(), xm.data());
      else for (int c = 0; c < amb; ++c) xm[static_cast<size_t>(c)] = blocks[b][static_cast<size_t>(c)] + delta[static_cast<size_t>(c)];
      std::vector<double*> pp = params, pm = params;
      pp[b] = xp.data();
      pm[b] = xm.data();
      std::vector<double> ep(static_cast<size_t>(nr)), em(static_cast<size_t>(nr));
      REQUIRE(cost.Evaluate(pp.data(), ep.data(), nullptr));
      REQUIRE(cost.Evaluate(pm.data(), em.data(), nullptr));
      for (int r = 0; r < nr; ++r) {
        INFO("block " << b << " tangent " << k << " residual " << r);
        CHECK(Jt(r, k) == Approx((ep[static_cast<size_t>(r)] - em[static_cast<size_t>(r)]) / (2 * h)).margin(2e-5).epsilon(1e-5));
      }
    }
  }
}

std::vector<double> PoseBlock(const SE3& T) {
  std::vector<double> p(7);
  PoseToParams(T, p.data());
  return p;
}

Eigen::Vector3d InFront(const SE3& T_cw, Rng& rng) {
  return T_cw.inverse() * Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-0.8, 0.8), rng.Uniform(0.8, 4.0));
}

Eigen::Vector3d RandomLine(Rng& rng) {
  const Eigen::Vector2d a(rng.Uniform(0, 640), rng.Uniform(0, 480)), b(rng.Uniform(0, 640), rng.Uniform(0, 480));
  const Eigen::Vector3d l = Eigen::Vector3d(a.x(), a.y(), 1).cross(Eigen::Vector3d(b.x(), b.y(), 1));
  return l / std::hypot(l.x(), l.y());
}

}  // namespace

TEST_CASE("structure residuals: line and plane Jacobians match numeric differentiation (pose-only and BA)") {
  Rng rng(13, "optim.test.structure");
  const Intrinsics K = SyntheticIntrinsics();
  const PoseManifold pose_manifold;
  const ceres::SphereManifold<3> sphere;
  for (int trial = 0; trial < 15; ++trial) {
    const SE3 T = StructurePose(rng);
    for (bool literal : {false, true}) {
      StructureResidualOptions opt;
      opt.literal_line = literal;
      LineObservation o;
      const Eigen::Vector3d Ps = InFront(T, rng), Pe = InFront(T, rng);
      o.X_w = {Ps, 0.5 * (Ps + Pe), Pe};
      o.l = RandomLine(rng);
      o.l_companion = RandomLine(rng);
      o.has_companion = trial % 2 == 0;
      o.weight = rng.Uniform(0.2, 1.0);
      CheckJacobians(LinePoseCost(K, o, opt), {PoseBlock(T)}, {&pose_manifold});
      CheckJacobians(LineBACost(K, o.l, o.has_companion ? &o.l_companion : nullptr, o.weight, opt),
                     {PoseBlock(T), {Ps.x(), Ps.y(), Ps.z(), Pe.x(), Pe.y(), Pe.z()}}, {&pose_manifold, nullptr});
      CheckJacobians(LineGaugePrior(Ps + Eigen::Vector3d(0.1, 0, 0), Pe, 0.1),
                     {{Ps.x(), Ps.y(), Ps.z(), Pe.x(), Pe.y(), Pe.z()}}, {nullptr});
    }
    // A plane seen from T: observed parameters near the true ones.
    const Eigen::Vector3d n_w = Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1)).normalized();
    const double d_w = rng.Uniform(-2, 2);
    const Eigen::Vector3d n_c = T.linear() * n_w;
    PlaneObservationResidual p;
    p.n_w = n_w, p.d_w = d_w;
    p.n_obs = (n_c + Eigen::Vector3d(0.05, -0.03, 0.02)).normalized();
    p.d_obs = d_w - n_c.dot(T.translation()) + 0.1;
    p.weight = rng.Uniform(0.2, 1.0);
    const StructureResidualOptions opt;
    CheckJacobians(PlanePoseCost(p, opt), {PoseBlock(T)}, {&pose_manifold});
    CheckJacobians(PlaneBACost(p.n_obs, p.d_obs, p.weight, opt), {PoseBlock(T), {n_w.x(), n_w.y(), n_w.z()}, {d_w}},
                   {&pose_manifold, &sphere, nullptr});
  }
}

TEST_CASE("structure residuals: hand-computed line and plane values") {
  Intrinsics K;
  K.fx = K.fy = 500, K.cx = 320, K.cy = 240;
  // Samples at z = 2 projecting to (320, 240), (420, 240), (520, 240); observed line v = 250
  // (l = (0, 1, -250)): each sample is 10 px above it, d = -10.
  const std::array<Eigen::Vector3d, 3> X = {Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0.4, 0, 2), Eigen::Vector3d(0.8, 0, 2)};
  const Eigen::Vector3d l(0, 1, -250), lc(0, 1, -200);  // companion v = 200: d' = +40
  double r[4];
  REQUIRE(LineResidualRaw(K, X, l, &lc, false, r, nullptr));
  CHECK(r[0] == Approx(-10));
  CHECK(r[1] == Approx(-10));
  CHECK(r[2] == Approx(-10));
  CHECK(r[3] == Approx(0).margin(1e-12));  // collinear and parallel: e_col = e_par = 0
  // Bend the middle sample 5 px down (v = 245): d_m = -5, e_col = -10 - 10 + 10 = -10, e_par = -10.
  std::array<Eigen::Vector3d, 3> Y = X;
  Y[1].y() = 5.0 * 2 / 500;
  REQUIRE(LineResidualRaw(K, Y, l, &lc, false, r, nullptr));
  CHECK(r[1] == Approx(-5));
  CHECK(r[3] == Approx(-20));
  REQUIRE(LineResidualRaw(K, Y, l, &lc, true, r, nullptr));
  CHECK(r[0] == Approx(-20));
  // Behind the camera: not evaluable.
  Y[2].z() = -1;
  CHECK_FALSE(LineResidualRaw(K, Y, l, nullptr, false, r, nullptr));

  // Plane z = 3 in the world (n = (0, 0, -1), d = 3), camera 1 m forward (t = -R C, C = (0, 0, 1)):
  // the camera sees it at distance 2 with the same normal.
  SE3 T = SE3::Identity();
  T.translation() = Eigen::Vector3d(0, 0, -1);
  PlaneObservationResidual p;
  p.n_w = Eigen::Vector3d(0, 0, -1), p.d_w = 3;
  p.n_obs = Eigen::Vector3d(0, 0, -1), p.d_obs = 2.5;
  const StructureResidualOptions opt;
  std::vector<double> raw;
  const double c = PlaneChi2(T, p, opt, &raw, nullptr);
  REQUIRE(raw.size() == 3);
  CHECK(raw[0] == Approx(0).margin(1e-12));
  CHECK(raw[1] == Approx(0).margin(1e-12));
  CHECK(raw[2] == Approx(-0.5));  // d_c = 3 - (0,0,-1).(0,0,-1) = 2; 2 - 2.5
  CHECK(c == Approx(0.25 / (0.02 * 0.02)));
  p.n_obs = Eigen::Vector3d(0, 0, 1);  // the other side
  CHECK(std::isinf(PlaneChi2(T, p, opt, nullptr, nullptr)));
}

namespace {

// A box room seen from the origin: 3 planes and 12 lines (edges of a box), observations at T_true.
void PlantStructure(const Intrinsics& K, const SE3& T_true, PoseStructure* st) {
  const std::vector<std::pair<Eigen::Vector3d, double>> planes = {
      {Eigen::Vector3d(0, 0, -1), 4.0}, {Eigen::Vector3d(0, -1, 0), 1.2}, {Eigen::Vector3d(1, 0, 0), 1.5}};
  for (size_t i = 0; i < planes.size(); ++i) {
    PlaneObservationResidual p;
    p.n_w = planes[i].first, p.d_w = planes[i].second;
    p.n_obs = T_true.linear() * p.n_w;
    p.d_obs = p.d_w - p.n_obs.dot(T_true.translation());
    p.obs_id = "pl" + std::to_string(i);
    st->planes.push_back(p);
  }
  const double x0 = -0.6, x1 = 0.6, y0 = -0.5, y1 = 0.5, z0 = 2.0, z1 = 3.0;
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges = {
      {{x0, y0, z0}, {x1, y0, z0}}, {{x0, y1, z0}, {x1, y1, z0}}, {{x0, y0, z0}, {x0, y1, z0}}, {{x1, y0, z0}, {x1, y1, z0}},
      {{x0, y0, z1}, {x1, y0, z1}}, {{x0, y1, z1}, {x1, y1, z1}}, {{x0, y0, z1}, {x0, y1, z1}}, {{x1, y0, z1}, {x1, y1, z1}},
      {{x0, y0, z0}, {x0, y0, z1}}, {{x1, y0, z0}, {x1, y0, z1}}, {{x0, y1, z0}, {x0, y1, z1}}, {{x1, y1, z0}, {x1, y1, z1}}};
  for (size_t i = 0; i < edges.size(); ++i) {
    LineObservation o;
    const Eigen::Vector3d a = edges[i].first, b = edges[i].second;
    o.X_w = {a, 0.5 * (a + b), b};
    const Eigen::Vector2d pa = K.Project(T_true * a), pb = K.Project(T_true * b);
    const Eigen::Vector3d l = Eigen::Vector3d(pa.x(), pa.y(), 1).cross(Eigen::Vector3d(pb.x(), pb.y(), 1));
    o.l = l / std::hypot(l.x(), l.y());
    o.obs_id = "ml" + std::to_string(i);
    st->lines.push_back(o);
  }
}

}  // namespace

TEST_CASE("structure residuals: pose-only optimisation recovers a pose from lines and planes alone") {
  const Intrinsics K = SyntheticIntrinsics();
  Rng rng(21, "optim.test.structure");
  for (int trial = 0; trial < 5; ++trial) {
    const SE3 T_true = StructurePose(rng, 0.1);
    PoseStructure st;
    PlantStructure(K, T_true, &st);
    const SE3 T0 = StructurePose(rng, 0.03) * T_true;
    const PoseOnlyResult r = OptimizePose(K, T0, {}, &st, PoseOnlyOptions{}, nullptr, "test");
    CHECK((r.T_cw.translation() - T_true.translation()).norm() < 1e-6);
    CHECK(Eigen::AngleAxisd(r.T_cw.linear() * T_true.linear().transpose()).angle() < 1e-6);
    CHECK(r.line_inliers == 12);
    CHECK(r.plane_inliers == 3);
    CHECK(r.num_inliers == 0);
  }
}

TEST_CASE("structure residuals: a wrong line is an outlier, and an empty structure is the point-only call") {
  const Intrinsics K = SyntheticIntrinsics();
  Rng rng(22, "optim.test.structure");
  const SE3 T_true = StructurePose(rng, 0.1);
  PoseStructure st;
  PlantStructure(K, T_true, &st);
  st.lines[3].l.z() += 30;  // 30 px off
  const PoseOnlyResult r = OptimizePose(K, StructurePose(rng, 0.02) * T_true, {}, &st, PoseOnlyOptions{}, nullptr, "t");
  CHECK(r.line_inlier[3] == 0);
  CHECK(r.line_inliers == 11);
  CHECK((r.T_cw.translation() - T_true.translation()).norm() < 1e-6);

  SyntheticPoseSpec spec;
  spec.num_points = 60;
  spec.seed = 7;
  const SyntheticPoseProblem prob = MakeSyntheticPoseProblem(spec);
  const PoseStructure empty;
  const PoseOnlyResult a = OptimizePose(K, prob.T_cw_init, prob.observations, PoseOnlyOptions{}, nullptr, "a");
  const PoseOnlyResult b = OptimizePose(K, prob.T_cw_init, prob.observations, &empty, PoseOnlyOptions{}, nullptr, "a");
  CHECK(a.T_cw.matrix() == b.T_cw.matrix());
  CHECK(a.inlier == b.inlier);
}

TEST_CASE("structure residuals: local BA refines map lines and planes and a free keyframe from structure alone") {
  const Intrinsics K = SyntheticIntrinsics();
  Rng rng(23, "optim.test.structure");
  // A 0.45 m baseline: the two views triangulate every line well.
  const SE3 T0 = SE3::Identity();
  SE3 T1 = StructurePose(rng, 0.1);
  T1.translation() += Eigen::Vector3d(0.4, -0.2, 0.05);
  PoseStructure s0, s1;
  PlantStructure(K, T0, &s0);
  PlantStructure(K, T1, &s1);
  LocalBAStructure st;
  for (size_t i = 0; i < s0.lines.size(); ++i) {
    BALine L;
    L.id = static_cast<int64_t>(i);
    // Perturbed endpoints along and across the line.
    L.P_s = s0.lines[i].X_w[0] + Eigen::Vector3d(rng.Uniform(-0.02, 0.02), rng.Uniform(-0.02, 0.02), rng.Uniform(-0.02, 0.02));
    L.P_e = s0.lines[i].X_w[2] + Eigen::Vector3d(rng.Uniform(-0.02, 0.02), rng.Uniform(-0.02, 0.02), rng.Uniform(-0.02, 0.02));
    st.lines.push_back(L);
    for (int k = 0; k < 2; ++k) {
      BALineObservation o;
      o.kf_id = k, o.line_id = L.id, o.l = (k == 0 ? s0 : s1).lines[i].l;
      st.line_observations.push_back(o);
    }
  }
  for (size_t i = 0; i < s0.planes.size(); ++i) {
    BAPlane P;
    P.id = static_cast<int64_t>(i);
    P.n = (s0.planes[i].n_w + Eigen::Vector3d(0.02, -0.01, 0.015)).normalized();
    P.d = s0.planes[i].d_w + 0.03;
    st.planes.push_back(P);
    for (int k = 0; k < 2; ++k) {
      BAPlaneObservation o;
      o.kf_id = k, o.plane_id = P.id;
      o.n_obs = (k == 0 ? s0 : s1).planes[i].n_obs, o.d_obs = (k == 0 ? s0 : s1).planes[i].d_obs;
      st.plane_observations.push_back(o);
    }
  }
  std::vector<BAKeyFrame> kfs(2);
  kfs[0].id = 0, kfs[0].T_cw = T0, kfs[0].fixed = true;
  kfs[1].id = 1, kfs[1].T_cw = StructurePose(rng, 0.01) * T1;
  LocalBAOptions o;
  o.iterations_robust = 10, o.iterations_refine = 20;
  const LocalBAResult r = LocalBundleAdjust(K, kfs, {}, {}, &st, o, nullptr, "ba");
  CHECK((r.T_cw.at(1).translation() - T1.translation()).norm() < 1e-4);
  for (size_t i = 0; i < s0.planes.size(); ++i) {
    CHECK(r.plane.at(static_cast<int64_t>(i)).first.dot(s0.planes[i].n_w) > std::cos(1e-4));
    CHECK(r.plane.at(static_cast<int64_t>(i)).second == Approx(s0.planes[i].d_w).margin(1e-4));
  }
  // Each refined line passes through the true one: its endpoints' distance to the true 3-D line.
  for (size_t i = 0; i < s0.lines.size(); ++i) {
    const Eigen::Vector3d a = s0.lines[i].X_w[0], dir = (s0.lines[i].X_w[2] - a).normalized();
    for (const Eigen::Vector3d& P : {r.line_P.at(static_cast<int64_t>(i)).first, r.line_P.at(static_cast<int64_t>(i)).second})
      CHECK(((P - a) - (P - a).dot(dir) * dir).norm() == Approx(0).margin(1e-3));
  }
  for (uint8_t f : r.line_inlier) CHECK(f == 1);
  for (uint8_t f : r.plane_inlier) CHECK(f == 1);
}
