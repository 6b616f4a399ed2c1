#include "render/chart.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/format.h"

namespace dynref::render {
namespace {

const Rgb kInk{0, 0, 0}, kGrid{225, 225, 225};

struct Frame {
  int left, top, width, height;  // plot area in pixels
};

// Title, axes box, grid and tick labels of one linear axis pair.
void DrawAxes(Canvas& c, const Frame& f, double x0, double x1, double y0, double y1, const std::string& title,
              const std::string& x_label, const std::string& y_label, bool x_ticks) {
  auto X = [&](double x) { return f.left + static_cast<int>(std::lround((x - x0) / (x1 - x0) * f.width)); };
  auto Y = [&](double y) { return f.top + f.height - static_cast<int>(std::lround((y - y0) / (y1 - y0) * f.height)); };
  if (x_ticks) {
    const double xs = NiceStep(x1 - x0, 8);
    for (long long i = static_cast<long long>(std::ceil(x0 / xs)); i * xs <= x1 + 1e-9 * xs; ++i) {
      const double x = static_cast<double>(i) * xs;
      c.Line(X(x), f.top, X(x), f.top + f.height, kGrid);
      c.Line(X(x), f.top + f.height, X(x), f.top + f.height + 5, kInk);
      const std::string t = TickText(x, xs);
      c.Text(X(x) - Canvas::TextWidth(t) / 2, f.top + f.height + 8, t, kInk);
    }
  }
  const double ys = NiceStep(y1 - y0, 6);
  for (long long i = static_cast<long long>(std::ceil(y0 / ys)); i * ys <= y1 + 1e-9 * ys; ++i) {
    const double y = static_cast<double>(i) * ys;
    c.Line(f.left, Y(y), f.left + f.width, Y(y), kGrid);
    c.Line(f.left - 5, Y(y), f.left, Y(y), kInk);
    const std::string t = TickText(y, ys);
    c.Text(f.left - 8 - Canvas::TextWidth(t), Y(y) - 7, t, kInk);
  }
  c.Rect(f.left, f.top, f.left + f.width, f.top + f.height, kInk);
  c.Text(f.left + f.width / 2 - Canvas::TextWidth(title) / 2, 8, title, kInk);
  c.Text(f.left + f.width / 2 - Canvas::TextWidth(x_label) / 2, f.top + f.height + 30, x_label, kInk);
  c.Text(8, f.top - 24, y_label, kInk);
}

// Legend entries (colour swatch + name) from (x, y) downwards.
void DrawLegend(Canvas& c, int x, int y, const std::vector<std::pair<std::string, Rgb>>& entries) {
  for (const auto& [name, colour] : entries) {
    c.FillRect(x, y + 3, x + 14, y + 11, colour);
    c.Text(x + 20, y, name.substr(0, 28), kInk);
    y += 18;
  }
}

}  // namespace

Rgb SeriesColour(size_t i) {
  static const Rgb k[] = {{0, 0, 0},       {230, 159, 0}, {86, 180, 233}, {0, 158, 115},
                          {213, 94, 0},    {0, 114, 178}, {204, 121, 167}, {240, 228, 66}};
  return k[i % 8];
}

double NiceStep(double range, int max_ticks) {
  if (!(range > 0) || !std::isfinite(range)) return 1.0;
  const double raw = range / max_ticks;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

std::string TickText(double v, double step) {
  if (step >= 1) return std::to_string(static_cast<long long>(std::llround(v)));
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 1, 6);
  return FormatFixed(v, decimals);
}

Canvas RenderLineChart(const std::vector<LineSeries>& series, const LineChartOptions& o) {
  const int right = 230;
  Frame f{80, 44, o.width - 80 - right, o.height - 44 - 60};
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const LineSeries& s : series)
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
        x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]), y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
  if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x1 - x0 < 1e-9) x0 -= 0.5, x1 += 0.5;
  if (y1 - y0 < 1e-9) y0 -= 0.5, y1 += 0.5;
  const double mx = 0.04 * (x1 - x0), my = 0.04 * (y1 - y0);
  x0 -= mx, x1 += mx, y0 -= my, y1 += my;
  if (o.equal_aspect) {  // widen the tighter axis so one metre is the same length both ways
    const double sx = (x1 - x0) / f.width, sy = (y1 - y0) / f.height, s = std::max(sx, sy);
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    x0 = cx - 0.5 * s * f.width, x1 = cx + 0.5 * s * f.width;
    y0 = cy - 0.5 * s * f.height, y1 = cy + 0.5 * s * f.height;
  }
  Canvas c(o.width, o.height, Rgb{255, 255, 255});
  DrawAxes(c, f, x0, x1, y0, y1, o.title, o.x_label, o.y_label, true);
  auto X = [&](double x) { return f.left + static_cast<int>(std::lround((x - x0) / (x1 - x0) * f.width)); };
  auto Y = [&](double y) { return f.top + f.height - static_cast<int>(std::lround((y - y0) / (y1 - y0) * f.height)); };
  std::vector<std::pair<std::string, Rgb>> legend;
  for (const LineSeries& s : series) {
    bool have = false;
    int px = 0, py = 0;
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        have = false;
        continue;
      }
      const int qx = X(s.x[i]), qy = Y(s.y[i]);
      if (have) c.Line(px, py, qx, qy, s.colour, s.thickness);
      px = qx, py = qy, have = true;
    }
    legend.push_back({s.name, s.colour});
  }
  DrawLegend(c, f.left + f.width + 16, f.top, legend);
  return c;
}

Canvas RenderBarChart(const std::vector<std::string>& groups, const std::vector<BarSeries>& series,
                      const BarChartOptions& o) {
  const int right = 250;
  Frame f{80, 44, o.width - 80 - right, o.height - 44 - 80};
  const auto tr = [&](double v) { return o.log_y ? std::log10(v) : v; };
  double y0 = o.log_y ? std::numeric_limits<double>::infinity() : 0.0, y1 = -std::numeric_limits<double>::infinity();
  for (const BarSeries& s : series)
    for (size_t g = 0; g < s.value.size(); ++g) {
      const double v = s.value[g], e = g < s.error.size() && std::isfinite(s.error[g]) ? s.error[g] : 0.0;
      if (!std::isfinite(v) || (o.log_y && v <= 0)) continue;
      y1 = std::max(y1, tr(v + e));
      y0 = std::min(y0, o.log_y ? tr(v) : std::min(0.0, v - e));
    }
  if (!std::isfinite(y1)) y0 = 0, y1 = 1;
  if (o.log_y) y0 = std::floor(y0), y1 = std::ceil(y1);
  if (y1 - y0 < 1e-12) y1 = y0 + 1;
  if (!o.log_y) y1 += 0.05 * (y1 - y0);
  Canvas c(o.width, o.height, Rgb{255, 255, 255});
  auto Y = [&](double y) { return f.top + f.height - static_cast<int>(std::lround((y - y0) / (y1 - y0) * f.height)); };
  if (o.log_y) {  // decades
    for (double d = y0; d <= y1 + 1e-9; d += 1) {
      c.Line(f.left, Y(d), f.left + f.width, Y(d), kGrid);
      const std::string t = FormatFixed(std::pow(10.0, d), d < 0 ? static_cast<int>(-d) : 0);
      c.Text(f.left - 8 - Canvas::TextWidth(t), Y(d) - 7, t, kInk);
    }
    c.Rect(f.left, f.top, f.left + f.width, f.top + f.height, kInk);
    c.Text(f.left + f.width / 2 - Canvas::TextWidth(o.title) / 2, 8, o.title, kInk);
    c.Text(8, f.top - 24, o.y_label + " (log scale)", kInk);
  } else {
    DrawAxes(c, f, 0, 1, y0, y1, o.title, "", o.y_label, false);
  }
  const int n = static_cast<int>(groups.size()), k = static_cast<int>(series.size());
  const int gw = n > 0 ? f.width / n : f.width;
  const int bw = std::max(2, (gw - 16) / std::max(1, k));
  const int base = Y(o.log_y ? y0 : std::max(y0, 0.0));
  for (int g = 0; g < n; ++g) {
    const int gx = f.left + g * gw + (gw - bw * k) / 2;
    for (int s = 0; s < k; ++s) {
      const BarSeries& bs = series[static_cast<size_t>(s)];
      if (static_cast<size_t>(g) >= bs.value.size()) continue;
      const double v = bs.value[static_cast<size_t>(g)];
      if (!std::isfinite(v) || (o.log_y && v <= 0)) continue;
      const int x = gx + s * bw, top = Y(tr(v));
      c.FillRect(x + 1, std::min(top, base), x + bw - 2, std::max(top, base), bs.colour);
      c.Rect(x + 1, std::min(top, base), x + bw - 2, std::max(top, base), kInk);
      if (static_cast<size_t>(g) < bs.error.size() && std::isfinite(bs.error[static_cast<size_t>(g)]) &&
          bs.error[static_cast<size_t>(g)] > 0) {
        const double e = bs.error[static_cast<size_t>(g)];
        const int hi = Y(tr(v + e)), lo = o.log_y && v - e <= 0 ? base : Y(tr(v - e)), cx = x + bw / 2;
        c.Line(cx, hi, cx, lo, kInk);
        c.Line(cx - 3, hi, cx + 3, hi, kInk);
        c.Line(cx - 3, lo, cx + 3, lo, kInk);
      }
    }
    const std::string label = groups[static_cast<size_t>(g)].substr(0, static_cast<size_t>(std::max(4, gw / 8)));
    c.Text(f.left + g * gw + gw / 2 - Canvas::TextWidth(label) / 2, f.top + f.height + 8, label, kInk);
  }
  std::vector<std::pair<std::string, Rgb>> legend;
  for (const BarSeries& s : series) legend.push_back({s.name, s.colour});
  DrawLegend(c, f.left + f.width + 16, f.top, legend);
  return c;
}

}  // namespace dynref::render
