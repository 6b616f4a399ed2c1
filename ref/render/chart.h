// Off-screen charts for the reproduce reports (PNG via Canvas: integer rasterisation, built-in
// bitmap font, so the bytes are the same on every machine): line charts (trajectories seen from
// above, errors over time) and grouped bar charts (ablations beside the paper's values, runtimes).
#pragma once
#include <string>
#include <vector>

#include "render/canvas.h"

namespace dynref::render {

// Okabe & Ito (2008) colour-blind-safe categorical colours; Series(i) cycles through 8.
Rgb SeriesColour(size_t i);
// Axis ticks: a 1-2-5 step giving at most max_ticks intervals over range; tick text with just
// enough decimals for the step.
double NiceStep(double range, int max_ticks);
std::string TickText(double v, double step);

struct LineSeries {
  std::string name;
  std::vector<double> x, y;  // same length; a NaN y breaks the line
  Rgb colour;
  int thickness = 1;
};

struct LineChartOptions {
  int width = 900, height = 600;
  std::string title, x_label, y_label;
  bool equal_aspect = false;  // same metres per pixel on both axes (a trajectory from above)
};

Canvas RenderLineChart(const std::vector<LineSeries>& series, const LineChartOptions& options);

struct BarSeries {
  std::string name;
  std::vector<double> value;  // one per group; NaN = no bar
  std::vector<double> error;  // optional +- bar per group (empty = none); NaN = none
  Rgb colour;
};

struct BarChartOptions {
  int width = 1000, height = 520;
  std::string title, y_label;
  bool log_y = false;         // log10 axis (values <= 0 are not drawn)
};

// Groups along x (e.g. sequences), one bar per series in each group, a legend on the right.
Canvas RenderBarChart(const std::vector<std::string>& groups, const std::vector<BarSeries>& series,
                      const BarChartOptions& options);

}  // namespace dynref::render
