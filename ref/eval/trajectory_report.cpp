#include "eval/trajectory_report.h"

#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/format.h"

namespace dynref {
namespace {

std::string ReportRow(const std::string& name, const ErrorStats& s, const std::string& unit, bool sse) {
  std::ostringstream o;
  o << "  " << name << " [" << unit << "]  rmse " << FormatFixed(s.rmse, 6) << "  mean "
    << FormatFixed(s.mean, 6) << "  median " << FormatFixed(s.median, 6) << "  std "
    << FormatFixed(s.std, 6) << "  min " << FormatFixed(s.min, 6) << "  max "
    << FormatFixed(s.max, 6);
  if (sse) o << "  sse " << FormatFixed(s.sse, 6);
  return o.str();
}

nlohmann::json ReportStatsJson(const ErrorStats& s) {
  return {{"count", s.count}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
          {"std", s.std},     {"min", s.min},   {"max", s.max},   {"sse", s.sse}};
}

AteOptions ReportAteOptions(const TrajectoryEvalOptions& a) {
  AteOptions ate_opt;
  ate_opt.association = a.assoc == "evo" ? AssociationKind::kEvo : AssociationKind::kTum;
  ate_opt.max_difference_s = a.max_diff;
  ate_opt.offset_s = a.offset;
  ate_opt.align = a.align == "sim3" ? AlignMode::kSim3
                  : a.align == "none" ? AlignMode::kNone
                                      : AlignMode::kSE3;
  ate_opt.Check();
  return ate_opt;
}

RpeOptions ReportRpeOptions(const TrajectoryEvalOptions& a) {
  RpeOptions rpe_opt;
  rpe_opt.delta = a.delta;
  rpe_opt.unit = a.delta_unit == "f" ? DeltaUnit::kFrames : DeltaUnit::kSeconds;
  rpe_opt.offset_s = a.offset;
  rpe_opt.mode = a.rpe_mode == "interp" ? RpeMode::kInterp : RpeMode::kTum;
  rpe_opt.Check();
  return rpe_opt;
}

std::string AteRowsText(const AteResult& ate) {
  return "ATE (absolute trajectory error, translation), " + std::to_string(ate.matches.size()) + " pairs\n" +
         ReportRow("ate", ate.stats, "m", true) + "\n";
}

// "(N poses; K duplicate stamp(s), ...)" of one input.
std::string PosesText(const TumTrajectory& t, bool evo) {
  std::string s = "  (" + std::to_string(t.poses.size()) + " poses";
  if (t.duplicate_stamps)
    s += "; " + std::to_string(t.duplicate_stamps) + " duplicate stamp(s), " +
         (evo ? "all kept as evo" : "later line kept as TUM");
  return s + ")\n";
}

}  // namespace

TrajectoryEvalReport EvaluateTrajectoryFiles(const TrajectoryEvalOptions& options, std::ostream& partial) {
  TrajectoryEvalReport r;
  r.options = options;
  r.ate_options = ReportAteOptions(options);
  r.rpe_options = ReportRpeOptions(options);
  // TUM's tools read files into a dict (the later of two equal stamps wins); evo keeps every
  // line. RPE (TUM mode) always uses the TUM reading.
  TumReadOptions tum_read;
  tum_read.duplicates = DuplicateStamps::kKeepLast;
  TumReadOptions evo_read;
  evo_read.duplicates = DuplicateStamps::kKeepAll;
  r.gt = ReadTumTrajectory(options.gt, tum_read);
  r.est = ReadTumTrajectory(options.est, tum_read);
  const bool evo = r.ate_options.association == AssociationKind::kEvo;
  r.gt_ate = evo ? ReadTumTrajectory(options.gt, evo_read) : r.gt;
  r.est_ate = evo ? ReadTumTrajectory(options.est, evo_read) : r.est;
  r.ate = ComputeAte(r.gt_ate, r.est_ate, r.ate_options);
  try {
    r.rpe = ComputeRpe(r.gt, r.est, r.rpe_options);
  } catch (const InputError&) {
    // ATE is still worth having (issue 20 item 10): print it, then report the RPE problem (exit 2).
    partial << "dynref eval\n" << AteRowsText(r.ate);
    throw;
  }
  return r;
}

std::string TrajectoryReportText(const TrajectoryEvalReport& r) {
  const TrajectoryEvalOptions& a = r.options;
  const bool evo = r.ate_options.association == AssociationKind::kEvo;
  const bool interp = r.rpe_options.mode == RpeMode::kInterp;
  const AlignMode align = r.ate_options.align;
  const std::string assoc_desc =
      evo ? "evo (nearest neighbour from the shorter trajectory, |dt| <= max-diff, not one-to-one)"
          : "tum (associate.py greedy one-to-one by smallest |dt|, |dt| < max-diff)";
  const std::string align_desc = align == AlignMode::kSE3    ? "se3 (Horn/Umeyama, rotation + translation, no scale)"
                                 : align == AlignMode::kSim3 ? "sim3 (Umeyama with scale)"
                                                             : "none (poses compared as given)";
  std::ostringstream o;
  o << "dynref eval\n"
    << "  ground truth   " << a.gt << PosesText(r.gt_ate, evo) << "  estimate       " << a.est
    << PosesText(r.est_ate, evo)
    << "  association    " << assoc_desc << ", max-diff " << FormatDouble17(a.max_diff)
    << " s, offset " << FormatDouble17(a.offset) << " s (added to the estimate's stamps)\n"
    << "  pairs used     " << r.ate.matches.size() << " of " << r.gt_ate.poses.size() << " gt / "
    << r.est_ate.poses.size() << " est poses\n"
    << "  alignment      " << align_desc << ", scale " << FormatFixed(r.ate.alignment.scale, 6) << "\n"
    << AteRowsText(r.ate) << "RPE (--rpe-mode " << a.rpe_mode
    << (interp ? ": evaluate_rpe.py --fixed_delta pairs incl. the one ending at the last pose, "
                 "ground truth interpolated"
               : " = evaluate_rpe.py --fixed_delta")
    << "), delta " << FormatDouble17(a.delta) << " "
    << (r.rpe_options.unit == DeltaUnit::kSeconds ? "s" : "frames")
    << ", every pair (no random sub-sampling)\n"
    << "  pairs          " << r.rpe.pairs.size() << " used of " << r.rpe.candidate_pairs
    << " candidates (dropped: ground truth "
    << (interp ? "missing or in a gap wider than" : "farther than") << " 2 x median gt interval = "
    << FormatFixed(r.rpe.gt_max_time_difference_s, 6) << " s)\n"
    << ReportRow("translational", r.rpe.trans_m, "m", false) << "\n"
    << ReportRow("rotational", r.rpe.rot_deg, "deg", false) << "\n";
  return o.str();
}

std::string TrajectoryReportJson(const TrajectoryEvalReport& r) {
  const TrajectoryEvalOptions& a = r.options;
  nlohmann::json j;
  j["tool"] = "dynref eval";
  j["ground_truth"] = {{"path", a.gt}, {"poses", r.gt_ate.poses.size()},
                       {"duplicate_stamps", r.gt_ate.duplicate_stamps}};
  j["estimate"] = {{"path", a.est}, {"poses", r.est_ate.poses.size()},
                   {"duplicate_stamps", r.est_ate.duplicate_stamps}};
  j["association"] = {{"kind", AssociationKindName(r.ate_options.association)},
                      {"max_diff_s", a.max_diff},
                      {"offset_s", a.offset},
                      {"pairs", r.ate.matches.size()}};
  const Similarity3& S = r.ate.alignment;
  j["alignment"] = {{"mode", AlignModeName(r.ate_options.align)},
                    {"scale", S.scale},
                    {"rotation_row_major",
                     {S.R(0, 0), S.R(0, 1), S.R(0, 2), S.R(1, 0), S.R(1, 1), S.R(1, 2), S.R(2, 0),
                      S.R(2, 1), S.R(2, 2)}},
                    {"translation", {S.t.x(), S.t.y(), S.t.z()}}};
  j["ate"] = {{"unit", "m"}, {"stats", ReportStatsJson(r.ate.stats)}};
  j["rpe"] = {{"mode", a.rpe_mode},
              {"delta", a.delta},
              {"delta_unit", DeltaUnitName(r.rpe_options.unit)},
              {"candidate_pairs", r.rpe.candidate_pairs},
              {"pairs", r.rpe.pairs.size()},
              {"random_subsampling", false},
              {"gt_max_time_difference_s", r.rpe.gt_max_time_difference_s},
              {"translational_m", ReportStatsJson(r.rpe.trans_m)},
              {"rotational_deg", ReportStatsJson(r.rpe.rot_deg)}};
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace dynref
