// OptimizePose / LocalBundleAdjust write one Residual record per observation at trace level full.
#include <catch2/catch.hpp>

#include "optim/optim.h"
#include "optim/synthetic_problem.h"
#include "test_support.h"
#include "trace/trace_reader.h"
#include "trace/trace_writer.h"

using namespace dynref;
using namespace dynref::optim;

namespace {

std::vector<trace::Record> ResidualRecords(const std::string& path) {
  trace::TraceReader reader(path);
  std::vector<trace::Record> out;
  for (size_t g = 0; g < reader.groups().size(); ++g) {
    for (const trace::Record& r : reader.ReadGroup(g)) {
      if (r.type == trace::RecordType::kResidual) out.push_back(r);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("trace: pose-only and local BA log one residual per observation") {
  const std::string dir = test::ScratchDir("optim_trace");
  const std::string path = dir + "/trace.dtr";
  SyntheticPoseSpec spec;
  spec.num_points = 50;
  const SyntheticPoseProblem p = MakeSyntheticPoseProblem(spec);
  SyntheticBASpec ba_spec;
  ba_spec.num_keyframes = 3;
  ba_spec.num_fixed = 1;
  ba_spec.num_points = 20;
  ba_spec.views_per_point = 2;
  const SyntheticBAProblem ba = MakeSyntheticBAProblem(ba_spec);
  PoseOnlyResult pose;
  LocalBAResult local;
  {
    trace::TraceWriter writer(path, trace::Level::kFull, trace::RunHeader{});
    writer.BeginFrame(0, 0.0);
    pose = OptimizePose(SyntheticIntrinsics(), p.T_cw_init, p.observations, PoseOnlyOptions{},
                        &writer, "track.pose#1");
    local = LocalBundleAdjust(SyntheticIntrinsics(), ba.keyframes, ba.points, ba.observations,
                              LocalBAOptions{}, &writer, "localba#1");
    writer.Close("complete");
  }
  const std::vector<trace::Record> records = ResidualRecords(path);
  REQUIRE(records.size() == p.observations.size() + ba.observations.size());
  for (size_t i = 0; i < p.observations.size(); ++i) {
    const trace::Record& r = records[i];
    CHECK(r.stage == "track.pose#1");
    CHECK(r.entity == p.observations[i].obs_id);
    // u_right < 0 (also a close point at the left border, as in ORB-SLAM2) => mono2
    const size_t dof = p.observations[i].u_right >= 0 ? 3 : 2;
    CHECK(r.residual_kind == (dof == 3 ? "rgbd3" : "mono2"));
    CHECK(r.residual_start.size() == dof);
    CHECK(r.residual_end.size() == dof);
    CHECK(r.information == p.observations[i].inv_sigma2);
    CHECK(r.inlier == (pose.inlier[i] != 0));
    if (r.inlier) CHECK(r.chi2 <= (dof == 3 ? 7.815 : 5.991));
    if (r.inlier) CHECK(r.robust_loss == r.chi2);  // Huber is quadratic inside the gate
  }
  for (size_t i = 0; i < ba.observations.size(); ++i) {
    const trace::Record& r = records[p.observations.size() + i];
    const BAObservation& o = ba.observations[i];
    CHECK(r.stage == "localba#1");
    CHECK(r.entity == "mp" + std::to_string(o.point_id) + "@kf" + std::to_string(o.kf_id));
    CHECK(r.residual_kind == (o.u_right >= 0 ? "rgbd3" : "mono2"));
    CHECK(r.inlier == (local.inlier[i] != 0));
  }
}
