#include "reproduce/report_plots.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "io/trajectory.h"
#include "reproduce/report_format.h"

namespace dynref::reproduce {
namespace {

struct Aligned {
  std::vector<double> t, err;             // seconds since the ground truth's start, ATE error
  std::vector<Eigen::Vector3d> position;  // aligned estimate
};

// The run's ATE alignment as dynref eval computes it; empty when it has no ATE.
Aligned AlignRun(const TumTrajectory& gt, const std::string& run_dir) {
  Aligned a;
  TumReadOptions ro;
  ro.allow_empty = true;
  const TumTrajectory est = ReadTumTrajectory(run_dir + "/trajectory.txt", ro);
  try {
    const AteResult ate = ComputeAte(gt, est, AteOptions{});
    const double t0 = gt.poses.empty() ? 0.0 : gt.poses.front().stamp;
    for (size_t i = 0; i < ate.matches.size(); ++i) {
      a.t.push_back(gt.poses[ate.matches[i].first].stamp - t0);
      a.err.push_back(ate.errors_m[i]);
      a.position.push_back(ate.alignment.Apply(est.poses[ate.matches[i].second].T_wc.translation()));
    }
  } catch (const InputError&) {
    // no ATE (too few poses): the run is left out of the plot
  }
  return a;
}

}  // namespace

render::Rgb Lighter(render::Rgb c) {
  return {static_cast<uint8_t>((c.r + 2 * 255) / 3), static_cast<uint8_t>((c.g + 2 * 255) / 3),
          static_cast<uint8_t>((c.b + 2 * 255) / 3)};
}

void PlotTrajectoriesTopView(const std::string& seq_dir, const LabelledRuns& runs, const std::string& title,
                             const std::string& png) {
  const TumTrajectory gt = ReadTumTrajectory(seq_dir + "/groundtruth.txt");
  // Axis of least extent of the ground truth = the viewing direction.
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const StampedPose& p : gt.poses)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p.T_wc.translation()[k]), hi[k] = std::max(hi[k], p.T_wc.translation()[k]);
  int drop = 0;
  for (int k = 1; k < 3; ++k)
    if (hi[k] - lo[k] < hi[drop] - lo[drop]) drop = k;
  const int ax = drop == 0 ? 1 : 0, ay = drop == 2 ? 1 : 2;
  const char* names[] = {"x", "y", "z"};
  std::vector<render::LineSeries> series;
  render::LineSeries g{"ground truth", {}, {}, render::SeriesColour(0), 3};
  for (const StampedPose& p : gt.poses) g.x.push_back(p.T_wc.translation()[ax]), g.y.push_back(p.T_wc.translation()[ay]);
  series.push_back(g);
  for (size_t i = 0; i < runs.size(); ++i) {
    const Aligned a = AlignRun(gt, runs[i].second);
    render::LineSeries s{runs[i].first, {}, {}, render::SeriesColour(i + 1), 1};
    for (const Eigen::Vector3d& p : a.position) s.x.push_back(p[ax]), s.y.push_back(p[ay]);
    series.push_back(s);
  }
  render::LineChartOptions o;
  o.title = title;
  o.x_label = std::string(names[ax]) + " [m]";
  o.y_label = std::string(names[ay]) + " [m]";
  o.equal_aspect = true;
  render::RenderLineChart(series, o).WritePng(png);
}

void PlotAteOverTime(const std::string& seq_dir, const LabelledRuns& runs, const std::string& title,
                     const std::string& png) {
  const TumTrajectory gt = ReadTumTrajectory(seq_dir + "/groundtruth.txt");
  std::vector<render::LineSeries> series;
  for (size_t i = 0; i < runs.size(); ++i) {
    const Aligned a = AlignRun(gt, runs[i].second);
    series.push_back({runs[i].first, a.t, a.err, render::SeriesColour(i + 1), 1});
  }
  render::LineChartOptions o;
  o.height = 420;
  o.title = title;
  o.x_label = "time [s]";
  o.y_label = "ATE error [m]";
  render::RenderLineChart(series, o).WritePng(png);
}

void PlotBars(const std::vector<std::string>& groups, const std::vector<render::BarSeries>& series,
              const render::BarChartOptions& options, const std::string& png) {
  render::RenderBarChart(groups, series, options).WritePng(png);
}

}  // namespace dynref::reproduce

namespace dynref::reproduce {

std::string AteBarsSection(const std::vector<std::string>& groups, const std::vector<SeedSeries>& ours,
                           const std::vector<PaperSeries>& paper, size_t colour_offset, const std::string& seeds_text,
                           const std::string& report) {
  std::vector<render::BarSeries> series;
  for (size_t v = 0; v < ours.size(); ++v) {
    render::BarSeries s{ours[v].label, {}, {}, render::SeriesColour(v + colour_offset)};
    for (const std::vector<double>& r : ours[v].per_group) {
      s.value.push_back(Mean(r));
      s.error.push_back(r.size() > 1 ? ComputeErrorStats(r).std : std::nan(""));
    }
    series.push_back(s);
  }
  for (const PaperSeries& p : paper)
    series.push_back({p.label, p.per_group, {}, Lighter(render::SeriesColour(p.of + colour_offset))});
  render::BarChartOptions bo;
  bo.width = 1400;
  bo.title = "ATE RMSE (mean +- S.D. over seeds " + seeds_text + "), paper values lighter";
  bo.y_label = "ATE RMSE [m]";
  bo.log_y = true;
  const std::filesystem::path out(report);
  const std::string png = (out.parent_path() / (out.stem().string() + ".png")).string();
  PlotBars(groups, series, bo, png);
  return "\n## Plot\n\n![ATE per sequence](" + std::filesystem::path(png).filename().string() + ")\n";
}

std::string PerSeedAteSection(const std::vector<std::string>& groups, const std::vector<SeedSeries>& ours,
                              const std::string& seeds_text) {
  std::string md = "\n## Per seed: ATE RMSE (m)\n\n| Sequence | Variant | seeds " + seeds_text + " |\n|---|---|---|\n";
  for (size_t g = 0; g < groups.size(); ++g)
    for (const SeedSeries& s : ours) {
      md += "| " + groups[g] + " | " + s.label + " |";
      for (double r : s.per_group[g]) md += " " + Num(r);
      md += " |\n";
    }
  return md;
}

void FinishAteReport(std::string md, const std::vector<std::string>& groups, const std::vector<SeedSeries>& ours,
                     const std::vector<PaperSeries>& paper, size_t colour_offset, const std::string& seeds_text,
                     const std::string& report) {
  md += AteBarsSection(groups, ours, paper, colour_offset, seeds_text, report);
  md += PerSeedAteSection(groups, ours, seeds_text);
  AtomicWriteFile(report, md);
  std::cout << "reproduce: wrote " << report << "\n";
}

}  // namespace dynref::reproduce
