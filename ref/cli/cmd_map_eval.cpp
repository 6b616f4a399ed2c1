// `dynref map-eval MAP --gt SEQ`: accuracy, completeness and ghost fraction of a dense map
// (PLY or PCD) against a synthetic sequence's scene ground truth (ref/eval/map_eval.h).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/command.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "dense/pcd_io.h"
#include "io/ply.h"
#include "eval/map_eval.h"
#include "eval/trajectory_eval.h"
#include "io/trajectory.h"

namespace fs = std::filesystem;

namespace dynref::cli {
namespace {

// %g text of a radius (0.05, not 0.050000000000000003).
std::string Short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

struct MapEvalArgs {
  std::string map, gt, trajectory, json, align = "first";
  MapEvalOptions options;
};

int RunMapEval(const MapEvalArgs& a) {
  const std::string ext = fs::path(a.map).extension().string();
  if (ext != ".ply" && ext != ".pcd") throw InputError(a.map, "map must be a .ply or .pcd point cloud");
  for (const char* f : {"static_scene.ply", "static_observed.ply", "movers_observed.ply"})
    if (!fs::exists(a.gt + "/gt/" + f))
      throw InputError(a.gt + "/gt/" + f, "missing: --gt needs a sequence written by dynref synth (scene ground truth)");
  const std::string traj = a.trajectory.empty() ? (fs::path(a.map).parent_path() / "trajectory.txt").string() : a.trajectory;
  const dense::PointCloud cloud = ext == ".ply" ? ReadPly(a.map) : dense::ReadPcd(a.map);
  // Accuracy and ghost fraction of no points are undefined, not 0 (issue 37).
  if (cloud.empty()) throw InputError(a.map, "the map has 0 points: nothing to evaluate");
  // The map lives in the run's world frame, anchored at its first camera (eval/map_eval.h).
  double traj_rmse = 0;
  const SE3 T = MapToGroundTruth(ReadTumTrajectory(a.gt + "/groundtruth.txt"), ReadTumTrajectory(traj),
                                 a.align == "first" ? MapAlign::kFirstCamera : MapAlign::kAte, &traj_rmse);
  std::vector<Eigen::Vector3d> map;
  map.reserve(cloud.size());
  for (const auto& p : cloud) map.push_back(T * Eigen::Vector3d(p.x, p.y, p.z));
  const MapEvalResult r = EvaluateMap(map, ReadPlyMesh(a.gt + "/gt/static_scene.ply"),
                                      ReadPly(a.gt + "/gt/static_observed.ply"),
                                      ReadPly(a.gt + "/gt/movers_observed.ply"), a.options);
  std::ostringstream o;
  o << "dynref map-eval\n  map            " << a.map << "  (" << r.map_points << " points)\n"
    << "  aligned with   " << traj << "  (" << (a.align == "first" ? "first camera onto its true pose" : "SE(3) ATE fit")
    << "; trajectory ATE RMSE " << FormatFixed(traj_rmse, 4) << " m)\n"
    << "  accuracy [m]   mean " << FormatFixed(r.accuracy.mean, 4) << "  median " << FormatFixed(r.accuracy.median, 4)
    << "  p95 " << FormatFixed(r.accuracy_p95, 4) << "  max " << FormatFixed(r.accuracy.max, 4)
    << "  (distance to the static scene mesh)\n"
    << "  completeness   " << FormatFixed(100.0 * r.completeness, 1) << " % of " << r.observed
    << " observed static 2 cm voxels have a map point within " << Short(a.options.complete_m) << " m\n"
    << "  ghosts         " << r.ghosts << " points, " << FormatFixed(100.0 * r.ghost_fraction, 2)
    << " % (within " << Short(a.options.ghost_m) << " m of a mover, farther from any static surface)\n";
  std::cout << o.str();
  if (!a.json.empty()) {
    nlohmann::json j = {{"map", a.map},
                        {"trajectory", traj},
                        {"align", a.align},
                        {"map_points", r.map_points},
                        {"alignment_ate_rmse_m", traj_rmse},
                        {"accuracy_m", {{"mean", r.accuracy.mean}, {"median", r.accuracy.median}, {"p95", r.accuracy_p95}, {"max", r.accuracy.max}}},
                        {"completeness", r.completeness},
                        {"completeness_radius_m", a.options.complete_m},
                        {"observed_static_voxels", r.observed},
                        {"ghosts", r.ghosts},
                        {"ghost_fraction", r.ghost_fraction},
                        {"ghost_radius_m", a.options.ghost_m}};
    AtomicWriteFile(a.json, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  }
  return kExitOk;
}

}  // namespace

void RegisterMapEvalCommand(CLI::App& root, CommandList& out) {
  auto a = std::make_shared<MapEvalArgs>();
  CLI::App* app = root.add_subcommand(
      "map-eval", "Dense map vs synthetic scene truth: accuracy, completeness at 5 cm, ghost fraction");
  app->add_option("MAP", a->map, "Map point cloud (.ply or .pcd), e.g. RUN/semantic_map.ply or RUN/dense_map.ply")->required();
  app->add_option("--gt", a->gt, "The synthetic sequence the run used (SEQ/gt/static_scene.ply ...)")->required();
  app->add_option("--trajectory", a->trajectory, "The run's trajectory (default: trajectory.txt beside MAP)");
  app->add_option("--json", a->json, "Also write the figures as JSON");
  app->add_option("--align", a->align, "first (default: the run's first camera onto its true pose) | ate (SE(3) fit of the trajectory)")
      ->check(CLI::IsMember({"first", "ate"}));
  app->add_option("--complete-m", a->options.complete_m, "Completeness radius in m (default 0.05)");
  app->add_option("--ghost-m", a->options.ghost_m, "Ghost radius in m (default 0.05)");
  out.push_back({app, [a] {
                   if (!(a->options.complete_m > 0) || !(a->options.ghost_m > 0))
                     throw InputError("--complete-m/--ghost-m", "radii must be > 0");
                   return RunMapEval(*a);
                 }});
}

}  // namespace dynref::cli
