#include "render/feature_plot.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/format.h"
#include "render/chart.h"

namespace dynref::render {
namespace {

// Categorical colours for stages (Okabe & Ito 2008, colour-blind safe), by sorted stage name.
const Rgb kStageColours[] = {{230, 159, 0}, {86, 180, 233}, {0, 158, 115}, {213, 94, 0},
                             {0, 114, 178}, {204, 121, 167}, {240, 228, 66}, {0, 0, 0}};

struct Point {
  double x, y, before;
  std::string stage, series;
};

}  // namespace

Canvas RenderFeaturePlot(const trace::FeatureHistory& h) {
  const int W = h.follow ? 1100 : 900, H = 440, left = 70, right = 230, top = 40, bottom = 90;
  Canvas c(W, H, Rgb{255, 255, 255});
  const Rgb ink{0, 0, 0}, grid{225, 225, 225};
  // Points: updates of one frame are spread over [frame, frame + 0.8) in processing order.
  std::map<int64_t, int> per_frame;
  // The backbone's structure records (stage "structure"), match records ("match.*") and records on
  // a residual observation id ("mp5@f1") carry geometry / a match / residual inputs with p = 0, not
  // probabilities: not drawn.
  const auto is_probability = [](const trace::FlatRecord& r) {
    return r.type == "prob" && !trace::IsCarrierStage(r.stage) && r.entity.find('@') == std::string::npos;
  };
  for (const auto& r : h.rows)
    if (is_probability(r)) ++per_frame[r.frame];
  std::map<int64_t, int> seen;
  std::vector<Point> pts;
  std::map<std::string, size_t> stages;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  bool any = false;
  for (const auto& r : h.rows) {
    if (!is_probability(r)) continue;
    double after = 0, before = 0;
    for (const auto& f : r.fields) {
      if (f.name == "after") after = f.number;
      if (f.name == "before") before = f.number;
    }
    const double x = static_cast<double>(r.frame) + 0.8 * seen[r.frame]++ / per_frame[r.frame];
    pts.push_back({x, after, before, r.stage, r.kind});  // one series per entity kind
    stages.emplace(r.stage, 0);
  }
  for (const auto& r : h.rows) {
    const double f = static_cast<double>(r.frame);
    if (!any) x_min = x_max = f, any = true;
    x_min = std::min(x_min, f), x_max = std::max(x_max, f + 1);
  }
  for (const Point& p : pts)
    if (std::isfinite(p.y) && std::isfinite(p.before))
      y_min = std::min({y_min, p.y, p.before}), y_max = std::max({y_max, p.y, p.before});
  size_t si = 0;
  for (auto& [name, idx] : stages) idx = si++;
  const int pw = W - left - right, ph = H - top - bottom;
  auto X = [&](double x) { return left + static_cast<int>(std::lround((x - x_min) / (x_max - x_min) * pw)); };
  auto Y = [&](double y) { return top + ph - static_cast<int>(std::lround((y - y_min) / (y_max - y_min) * ph)); };
  // Grid, ticks and labels.
  const double xs = std::max(1.0, NiceStep(x_max - x_min, 10)), ys = NiceStep(y_max - y_min, 5);
  for (double x = std::ceil(x_min / xs) * xs; x <= x_max + 1e-9; x += xs) {
    c.Line(X(x), top, X(x), top + ph, grid);
    c.Line(X(x), top + ph, X(x), top + ph + 5, ink);
    const std::string t = TickText(x, xs);
    c.Text(X(x) - Canvas::TextWidth(t) / 2, top + ph + 8, t, ink);
  }
  for (double y = std::ceil(y_min / ys) * ys; y <= y_max + 1e-9; y += ys) {
    c.Line(left, Y(y), left + pw, Y(y), grid);
    c.Line(left - 5, Y(y), left, Y(y), ink);
    const std::string t = TickText(y, ys);
    c.Text(left - 8 - Canvas::TextWidth(t), Y(y) - 7, t, ink);
  }
  c.Rect(left, top, left + pw, top + ph, ink);
  c.Text(left + pw / 2 - Canvas::TextWidth("frame") / 2, H - 26, "frame", ink);
  c.Text(8, top - 28, "p(dynamic)", ink);
  const std::string title =
      h.follow ? h.id + " followed (" + std::to_string(h.chain.size()) + " linked entities): p(dynamic) updates"
               : h.id + ": probability updates across frames";
  c.Text(left + pw / 2 - Canvas::TextWidth(title) / 2, 8, title, ink);
  // Series per entity kind (a map point's history joins its per-frame feature observations):
  // a grey line from the previous value, then the jump (before -> after) in stage colour.
  std::map<std::string, const Point*> last;
  for (const Point& p : pts) {
    const Rgb col = kStageColours[stages[p.stage] % 8];
    auto it = last.find(p.series);
    if (it != last.end()) c.Line(X(it->second->x), Y(it->second->y), X(p.x), Y(it->second->y), Rgb{90, 90, 90});
    c.Line(X(p.x), Y(p.before), X(p.x), Y(p.y), col, 3);
    last[p.series] = &p;
  }
  for (const Point& p : pts) {
    const Rgb col = kStageColours[stages[p.stage] % 8];
    c.Disc(X(p.x), Y(p.y), 4, ink);
    c.Disc(X(p.x), Y(p.y), 3, col);
  }
  // Decisions under the axis, one row per decision of the frame (up to three rows).
  std::map<int64_t, int> decisions_in_frame;
  for (const auto& r : h.rows) {
    if (r.type != "decision") continue;
    const bool kept = r.fields.at(0).text == "1";
    const int row = std::min(decisions_in_frame[r.frame]++, 2);
    const int x = X(static_cast<double>(r.frame) + 0.4), y = top + ph + 30 + 11 * row;
    if (kept) {
      for (int k = 0; k < 6; ++k) c.Line(x - k, y + k - 3, x + k, y + k - 3, Rgb{0, 150, 60});
    } else {
      c.Line(x - 4, y - 4, x + 4, y + 4, Rgb{210, 30, 30}, 3);
      c.Line(x - 4, y + 4, x + 4, y - 4, Rgb{210, 30, 30}, 3);
    }
  }
  // Legend: stages, decisions.
  int ly = top;
  const int lx = left + pw + 16;
  c.Text(lx, ly, "stage of jump:", ink);
  ly += 20;
  for (const auto& [name, idx] : stages) {
    c.Disc(lx + 6, ly + 7, 4, ink);
    c.Disc(lx + 6, ly + 7, 3, kStageColours[idx % 8]);
    c.Text(lx + 16, ly, name.substr(0, 24), ink);
    ly += 18;
  }
  ly += 10;
  for (int k = 0; k < 6; ++k) c.Line(lx + 6 - k, ly + 4 + k, lx + 6 + k, ly + 4 + k, Rgb{0, 150, 60});
  c.Text(lx + 16, ly, "kept (decision)", ink);
  ly += 18;
  c.Line(lx + 2, ly + 3, lx + 10, ly + 11, Rgb{210, 30, 30}, 3);
  c.Line(lx + 2, ly + 11, lx + 10, ly + 3, Rgb{210, 30, 30}, 3);
  c.Text(lx + 16, ly, "rejected", ink);
  if (pts.empty()) c.Text(left + 20, top + 20, "no probability updates for " + h.id, ink);
  return c;
}

void WriteFeaturePlot(const trace::FeatureHistory& history, const std::string& png_path) {
  RenderFeaturePlot(history).WritePng(png_path);
}

}  // namespace dynref::render
