// `dynref eval --gt G --est E`: ATE and RPE as TUM's evaluate_ate.py / evaluate_rpe.py and evo.
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/command.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "eval/trajectory_eval.h"

namespace dynref::cli {
namespace {

struct EvalArgs {
  std::string gt, est, json, save_rpe;
  double max_diff = 0.02;
  double offset = 0.0;
  std::string assoc = "tum", align = "se3", delta_unit = "s", rpe_mode = "tum";
  double delta = 1.0;
};

std::string Row(const std::string& name, const ErrorStats& s, const std::string& unit, bool sse) {
  std::ostringstream o;
  o << "  " << name << " [" << unit << "]  rmse " << FormatFixed(s.rmse, 6) << "  mean "
    << FormatFixed(s.mean, 6) << "  median " << FormatFixed(s.median, 6) << "  std "
    << FormatFixed(s.std, 6) << "  min " << FormatFixed(s.min, 6) << "  max "
    << FormatFixed(s.max, 6);
  if (sse) o << "  sse " << FormatFixed(s.sse, 6);
  return o.str();
}

nlohmann::json StatsJson(const ErrorStats& s) {
  return {{"count", s.count}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
          {"std", s.std},     {"min", s.min},   {"max", s.max},   {"sse", s.sse}};
}

int RunEval(const EvalArgs& a) {
  AteOptions ate_opt;
  ate_opt.association = a.assoc == "evo" ? AssociationKind::kEvo : AssociationKind::kTum;
  ate_opt.max_difference_s = a.max_diff;
  ate_opt.offset_s = a.offset;
  ate_opt.align = a.align == "sim3" ? AlignMode::kSim3
                  : a.align == "none" ? AlignMode::kNone
                                      : AlignMode::kSE3;
  ate_opt.Check();
  RpeOptions rpe_opt;
  rpe_opt.delta = a.delta;
  rpe_opt.unit = a.delta_unit == "f" ? DeltaUnit::kFrames : DeltaUnit::kSeconds;
  rpe_opt.offset_s = a.offset;
  rpe_opt.mode = a.rpe_mode == "interp" ? RpeMode::kInterp : RpeMode::kTum;
  rpe_opt.Check();

  // TUM's tools read files into a dict (the later of two equal stamps wins); evo keeps every
  // line. RPE (TUM mode) always uses the TUM reading.
  TumReadOptions tum_read;
  tum_read.duplicates = DuplicateStamps::kKeepLast;
  TumReadOptions evo_read;
  evo_read.duplicates = DuplicateStamps::kKeepAll;
  const TumTrajectory gt = ReadTumTrajectory(a.gt, tum_read);
  const TumTrajectory est = ReadTumTrajectory(a.est, tum_read);
  const bool evo = ate_opt.association == AssociationKind::kEvo;
  const TumTrajectory gt_ate = evo ? ReadTumTrajectory(a.gt, evo_read) : gt;
  const TumTrajectory est_ate = evo ? ReadTumTrajectory(a.est, evo_read) : est;

  const AteResult ate = ComputeAte(gt_ate, est_ate, ate_opt);
  RpeResult rpe;
  try {
    rpe = ComputeRpe(gt, est, rpe_opt);
  } catch (const InputError&) {
    // ATE is still worth having (issue 20 item 10): print it, then report the RPE problem (exit 2).
    std::cout << "dynref eval\nATE (absolute trajectory error, translation), " << ate.matches.size() << " pairs\n"
              << Row("ate", ate.stats, "m", true) << "\n";
    throw;
  }
  const bool interp = rpe_opt.mode == RpeMode::kInterp;

  const std::string assoc_desc =
      evo ? "evo (nearest neighbour from the shorter trajectory, |dt| <= max-diff, not one-to-one)"
          : "tum (associate.py greedy one-to-one by smallest |dt|, |dt| < max-diff)";
  const std::string align_desc =
      ate_opt.align == AlignMode::kSE3    ? "se3 (Horn/Umeyama, rotation + translation, no scale)"
      : ate_opt.align == AlignMode::kSim3 ? "sim3 (Umeyama with scale)"
                                          : "none (poses compared as given)";
  std::ostringstream o;
  o << "dynref eval\n"
    << "  ground truth   " << a.gt << "  (" << gt_ate.poses.size() << " poses";
  if (gt_ate.duplicate_stamps)
    o << "; " << gt_ate.duplicate_stamps << " duplicate stamp(s), "
      << (evo ? "all kept as evo" : "later line kept as TUM");
  o << ")\n  estimate       " << a.est << "  (" << est_ate.poses.size() << " poses";
  if (est_ate.duplicate_stamps)
    o << "; " << est_ate.duplicate_stamps << " duplicate stamp(s), "
      << (evo ? "all kept as evo" : "later line kept as TUM");
  o << ")\n"
    << "  association    " << assoc_desc << ", max-diff " << FormatDouble17(a.max_diff)
    << " s, offset " << FormatDouble17(a.offset) << " s (added to the estimate's stamps)\n"
    << "  pairs used     " << ate.matches.size() << " of " << gt_ate.poses.size() << " gt / "
    << est_ate.poses.size() << " est poses\n"
    << "  alignment      " << align_desc << ", scale " << FormatFixed(ate.alignment.scale, 6)
    << "\n"
    << "ATE (absolute trajectory error, translation), " << ate.matches.size() << " pairs\n"
    << Row("ate", ate.stats, "m", true) << "\n"
    << "RPE (--rpe-mode " << a.rpe_mode
    << (interp ? ": evaluate_rpe.py --fixed_delta pairs incl. the one ending at the last pose, "
                 "ground truth interpolated"
               : " = evaluate_rpe.py --fixed_delta")
    << "), delta " << FormatDouble17(a.delta) << " "
    << (rpe_opt.unit == DeltaUnit::kSeconds ? "s" : "frames")
    << ", every pair (no random sub-sampling)\n"
    << "  pairs          " << rpe.pairs.size() << " used of " << rpe.candidate_pairs
    << " candidates (dropped: ground truth "
    << (interp ? "missing or in a gap wider than" : "farther than") << " 2 x median gt interval = "
    << FormatFixed(rpe.gt_max_time_difference_s, 6) << " s)\n"
    << Row("translational", rpe.trans_m, "m", false) << "\n"
    << Row("rotational", rpe.rot_deg, "deg", false) << "\n";
  std::cout << o.str();

  if (!a.save_rpe.empty()) WriteRpePairs(a.save_rpe, est, rpe);
  if (!a.json.empty()) {
    nlohmann::json j;
    j["tool"] = "dynref eval";
    j["ground_truth"] = {{"path", a.gt}, {"poses", gt_ate.poses.size()},
                         {"duplicate_stamps", gt_ate.duplicate_stamps}};
    j["estimate"] = {{"path", a.est}, {"poses", est_ate.poses.size()},
                     {"duplicate_stamps", est_ate.duplicate_stamps}};
    j["association"] = {{"kind", AssociationKindName(ate_opt.association)},
                        {"max_diff_s", a.max_diff},
                        {"offset_s", a.offset},
                        {"pairs", ate.matches.size()}};
    const Similarity3& S = ate.alignment;
    j["alignment"] = {{"mode", AlignModeName(ate_opt.align)},
                      {"scale", S.scale},
                      {"rotation_row_major",
                       {S.R(0, 0), S.R(0, 1), S.R(0, 2), S.R(1, 0), S.R(1, 1), S.R(1, 2), S.R(2, 0),
                        S.R(2, 1), S.R(2, 2)}},
                      {"translation", {S.t.x(), S.t.y(), S.t.z()}}};
    j["ate"] = {{"unit", "m"}, {"stats", StatsJson(ate.stats)}};
    j["rpe"] = {{"mode", a.rpe_mode},
                {"delta", a.delta},
                {"delta_unit", DeltaUnitName(rpe_opt.unit)},
                {"candidate_pairs", rpe.candidate_pairs},
                {"pairs", rpe.pairs.size()},
                {"random_subsampling", false},
                {"gt_max_time_difference_s", rpe.gt_max_time_difference_s},
                {"translational_m", StatsJson(rpe.trans_m)},
                {"rotational_deg", StatsJson(rpe.rot_deg)}};
    AtomicWriteFile(a.json, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  }
  return kExitOk;
}

}  // namespace

void RegisterEvalCommand(CLI::App& root, CommandList& out) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* app = root.add_subcommand(
      "eval",
      "ATE and RPE of an estimated TUM trajectory against ground truth; reproduces TUM's "
      "evaluate_ate.py / evaluate_rpe.py (--assoc tum) and evo_ape -a (--assoc evo)");
  app->add_option("--gt", args->gt, "Ground-truth TUM trajectory (stamp tx ty tz qx qy qz qw)")
      ->required();
  app->add_option("--est", args->est, "Estimated TUM trajectory")->required();
  app->add_option("--max-diff", args->max_diff, "Association max time difference in s")
      ->capture_default_str();
  app->add_option("--offset", args->offset,
                  "Time offset in s added to the estimate's stamps before matching ground truth "
                  "(evaluate_ate.py / evaluate_rpe.py --offset, evo --t_offset)")
      ->capture_default_str();
  app->add_option("--assoc", args->assoc,
                  "tum: associate.py greedy one-to-one (evaluate_ate.py); evo: nearest "
                  "neighbour as evo_ape --t_max_diff")
      ->check(CLI::IsMember({"tum", "evo"}))
      ->capture_default_str();
  app->add_option("--align", args->align,
                  "ATE alignment: se3 (evaluate_ate.py, evo_ape -a), sim3 (evo_ape -as), none")
      ->check(CLI::IsMember({"se3", "sim3", "none"}))
      ->capture_default_str();
  app->add_option("--delta", args->delta, "RPE fixed delta (evaluate_rpe.py --delta)")
      ->capture_default_str();
  app->add_option("--delta-unit", args->delta_unit, "RPE delta unit: s (seconds) or f (frames)")
      ->check(CLI::IsMember({"s", "f"}))
      ->capture_default_str();
  app->add_option("--rpe-mode", args->rpe_mode,
                  "RPE pairs: tum = evaluate_rpe.py --fixed_delta, every pair; interp = the same "
                  "pairs plus the one ending at the last pose, ground truth interpolated at the "
                  "stamps (lerp + slerp)")
      ->check(CLI::IsMember({"tum", "interp"}))
      ->capture_default_str();
  app->add_option("--save-rpe", args->save_rpe,
                  "Write every RPE pair as evaluate_rpe.py --save does: stamp_est0 stamp_est1 "
                  "stamp_gt0 stamp_gt1 trans_error[m] rot_error[rad] (atomically)");
  app->add_option("--json", args->json, "Also write the results as JSON (atomically)");
  out.push_back({app, [args] { return RunEval(*args); }});
}

}  // namespace dynref::cli
