// PNG plots beside the reproduce reports (render/chart: deterministic bytes): trajectories seen
// from above, ATE over time, ablation bars with the paper's values, runtime bars.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "render/chart.h"

namespace dynref::reproduce {

// (label, run folder) of runs on one sequence.
using LabelledRuns = std::vector<std::pair<std::string, std::string>>;

// Ground truth and every run's trajectory after its ATE alignment (SE(3), TUM associate), seen
// along the ground truth's axis of least extent (the two others are the plot's axes).
void PlotTrajectoriesTopView(const std::string& seq_dir, const LabelledRuns& runs, const std::string& title,
                             const std::string& png);
// Each run's ATE error per associated pose against seconds since the sequence's first stamp.
void PlotAteOverTime(const std::string& seq_dir, const LabelledRuns& runs, const std::string& title,
                     const std::string& png);
// A grouped bar chart written as PNG (render::RenderBarChart).
void PlotBars(const std::vector<std::string>& groups, const std::vector<render::BarSeries>& series,
              const render::BarChartOptions& options, const std::string& png);
// The lighter twin of a series colour (the paper's bars beside ours).
render::Rgb Lighter(render::Rgb c);

// One of our variants over the groups (sequences): per group, its ATE RMSE of each seed.
struct SeedSeries {
  std::string label;
  std::vector<std::vector<double>> per_group;
};
// A paper column over the same groups, drawn in the lighter colour of ours[of].
struct PaperSeries {
  std::string label;
  std::vector<double> per_group;
  size_t of = 0;
};
// The ATE bar chart of a report (ours: mean +- S.D. over seeds in SeriesColour(i + colour_offset);
// the paper's lighter), written beside `report` as <stem>.png; returns the Markdown "## Plot"
// section that shows it.
std::string AteBarsSection(const std::vector<std::string>& groups, const std::vector<SeedSeries>& ours,
                           const std::vector<PaperSeries>& paper, size_t colour_offset, const std::string& seeds_text,
                           const std::string& report);
// "## Per seed: ATE RMSE (m)": one row per group and variant, the seeds' values in order.
std::string PerSeedAteSection(const std::vector<std::string>& groups, const std::vector<SeedSeries>& ours,
                              const std::string& seeds_text);
// A report's last step: appends AteBarsSection and PerSeedAteSection to `md`, writes `report`
// atomically and says so on stdout.
void FinishAteReport(std::string md, const std::vector<std::string>& groups, const std::vector<SeedSeries>& ours,
                     const std::vector<PaperSeries>& paper, size_t colour_offset, const std::string& seeds_text,
                     const std::string& report);

}  // namespace dynref::reproduce
