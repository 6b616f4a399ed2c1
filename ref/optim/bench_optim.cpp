// bench_optim: milliseconds per OptimizePose (~600 observations) and per LocalBundleAdjust
// (~10 keyframes / 3000 points / 15000 observations) on synthetic problems, one core.
// Usage: bench_optim [pose_repeats=50] [ba_repeats=3]. Not a test: timings are process CPU time.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "optim/optim.h"
#include "optim/synthetic_problem.h"

namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Process CPU time (single-threaded code: robust against other processes sharing the cores).
double NowMs() { return 1000.0 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace

int main(int argc, char** argv) {
  using namespace dynref::optim;
  const int pose_repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 50;
  const int ba_repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  const Intrinsics K = SyntheticIntrinsics();

  SyntheticPoseSpec pose_spec;
  pose_spec.num_points = 600;
  pose_spec.outlier_ratio = 0.1;
  const SyntheticPoseProblem pose = MakeSyntheticPoseProblem(pose_spec);
  std::vector<double> pose_ms;
  int inliers = 0;
  for (int r = 0; r < pose_repeats; ++r) {
    const double t0 = NowMs();
    const PoseOnlyResult res = OptimizePose(K, pose.T_cw_init, pose.observations, PoseOnlyOptions{},
                                            nullptr, "bench.pose");
    pose_ms.push_back(NowMs() - t0);
    inliers = res.num_inliers;
  }
  std::printf(
      "OptimizePose: %zu observations, %d inliers, median %.3f CPU ms/call (min %.3f) over %d "
      "calls\n",
      pose.observations.size(), inliers, Median(pose_ms),
      *std::min_element(pose_ms.begin(), pose_ms.end()), pose_repeats);

  SyntheticBASpec ba_spec;  // 10 keyframes (2 fixed), 3000 points, 5 views per point
  const SyntheticBAProblem ba = MakeSyntheticBAProblem(ba_spec);
  std::vector<double> ba_ms;
  int ba_inliers = 0;
  for (int r = 0; r < ba_repeats; ++r) {
    const double t0 = NowMs();
    const LocalBAResult res = LocalBundleAdjust(K, ba.keyframes, ba.points, ba.observations,
                                                LocalBAOptions{}, nullptr, "bench.localba");
    ba_ms.push_back(NowMs() - t0);
    ba_inliers = res.num_inliers;
  }
  std::printf(
      "LocalBundleAdjust: %zu keyframes, %zu points, %zu observations, %d inliers, "
      "median %.3f CPU ms/call (min %.3f) over %d calls\n",
      ba.keyframes.size(), ba.points.size(), ba.observations.size(), ba_inliers, Median(ba_ms),
      *std::min_element(ba_ms.begin(), ba_ms.end()), ba_repeats);
  return 0;
}
