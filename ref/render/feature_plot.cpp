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

// The backbone's structure records (stage "structure"), match records ("match.*") and records on
// a residual observation id ("mp5@f1") carry geometry / a match / residual inputs with p = 0, not
// probabilities: not drawn.
bool FeaturePlotIsProbability(const trace::FlatRecord& r) {
  return r.type == "prob" && !trace::IsCarrierStage(r.stage) && r.entity.find('@') == std::string::npos;
}

// Points: updates of one frame are spread over [frame, frame + 0.8) in processing order; one
// series per entity kind. Fills the stages seen (index assigned later).
std::vector<Point> FeaturePlotPoints(const trace::FeatureHistory& h, std::map<std::string, size_t>* stages) {
  std::map<int64_t, int> per_frame;
  for (const auto& r : h.rows)
    if (FeaturePlotIsProbability(r)) ++per_frame[r.frame];
  std::map<int64_t, int> seen;
  std::vector<Point> pts;
  for (const auto& r : h.rows) {
    if (!FeaturePlotIsProbability(r)) continue;
    double after = 0, before = 0;
    for (const auto& f : r.fields) {
      if (f.name == "after") after = f.number;
      if (f.name == "before") before = f.number;
    }
    const double x = static_cast<double>(r.frame) + 0.8 * seen[r.frame]++ / per_frame[r.frame];
    pts.push_back({x, after, before, r.stage, r.kind});  // one series per entity kind
    stages->emplace(r.stage, 0);
  }
  return pts;
}

// The plot area in pixels and the data range it shows.
struct FeaturePlotArea {
  int left, top, pw, ph;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  int X(double x) const { return left + static_cast<int>(std::lround((x - x_min) / (x_max - x_min) * pw)); }
  int Y(double y) const { return top + ph - static_cast<int>(std::lround((y - y_min) / (y_max - y_min) * ph)); }
};

// x: every record's frame range; y: [0, 1] widened to every finite before / after.
void FeaturePlotRange(const trace::FeatureHistory& h, const std::vector<Point>& pts, FeaturePlotArea* a) {
  bool any = false;
  for (const auto& r : h.rows) {
    const double f = static_cast<double>(r.frame);
    if (!any) a->x_min = a->x_max = f, any = true;
    a->x_min = std::min(a->x_min, f), a->x_max = std::max(a->x_max, f + 1);
  }
  for (const Point& p : pts)
    if (std::isfinite(p.y) && std::isfinite(p.before))
      a->y_min = std::min({a->y_min, p.y, p.before}), a->y_max = std::max({a->y_max, p.y, p.before});
}

// Grid, ticks and labels, frame, axis titles and the plot title.
void FeaturePlotAxes(const FeaturePlotArea& a, int H, const std::string& title, Canvas* c) {
  const Rgb ink{0, 0, 0}, grid{225, 225, 225};
  const int left = a.left, top = a.top, pw = a.pw, ph = a.ph;
  const double xs = std::max(1.0, NiceStep(a.x_max - a.x_min, 10)), ys = NiceStep(a.y_max - a.y_min, 5);
  for (double x = std::ceil(a.x_min / xs) * xs; x <= a.x_max + 1e-9; x += xs) {
    c->Line(a.X(x), top, a.X(x), top + ph, grid);
    c->Line(a.X(x), top + ph, a.X(x), top + ph + 5, ink);
    const std::string t = TickText(x, xs);
    c->Text(a.X(x) - Canvas::TextWidth(t) / 2, top + ph + 8, t, ink);
  }
  for (double y = std::ceil(a.y_min / ys) * ys; y <= a.y_max + 1e-9; y += ys) {
    c->Line(left, a.Y(y), left + pw, a.Y(y), grid);
    c->Line(left - 5, a.Y(y), left, a.Y(y), ink);
    const std::string t = TickText(y, ys);
    c->Text(left - 8 - Canvas::TextWidth(t), a.Y(y) - 7, t, ink);
  }
  c->Rect(left, top, left + pw, top + ph, ink);
  c->Text(left + pw / 2 - Canvas::TextWidth("frame") / 2, H - 26, "frame", ink);
  c->Text(8, top - 28, "p(dynamic)", ink);
  c->Text(left + pw / 2 - Canvas::TextWidth(title) / 2, 8, title, ink);
}

// Series per entity kind (a map point's history joins its per-frame feature observations):
// a grey line from the previous value, then the jump (before -> after) in stage colour.
void FeaturePlotSeries(const FeaturePlotArea& a, const std::vector<Point>& pts,
                       std::map<std::string, size_t>& stages, Canvas* c) {
  const Rgb ink{0, 0, 0};
  std::map<std::string, const Point*> last;
  for (const Point& p : pts) {
    const Rgb col = kStageColours[stages[p.stage] % 8];
    auto it = last.find(p.series);
    if (it != last.end()) c->Line(a.X(it->second->x), a.Y(it->second->y), a.X(p.x), a.Y(it->second->y), Rgb{90, 90, 90});
    c->Line(a.X(p.x), a.Y(p.before), a.X(p.x), a.Y(p.y), col, 3);
    last[p.series] = &p;
  }
  for (const Point& p : pts) {
    const Rgb col = kStageColours[stages[p.stage] % 8];
    c->Disc(a.X(p.x), a.Y(p.y), 4, ink);
    c->Disc(a.X(p.x), a.Y(p.y), 3, col);
  }
}

// Decisions under the axis, one row per decision of the frame (up to three rows).
void FeaturePlotDecisions(const FeaturePlotArea& a, const trace::FeatureHistory& h, Canvas* c) {
  std::map<int64_t, int> decisions_in_frame;
  for (const auto& r : h.rows) {
    if (r.type != "decision") continue;
    const bool kept = r.fields.at(0).text == "1";
    const int row = std::min(decisions_in_frame[r.frame]++, 2);
    const int x = a.X(static_cast<double>(r.frame) + 0.4), y = a.top + a.ph + 30 + 11 * row;
    if (kept) {
      for (int k = 0; k < 6; ++k) c->Line(x - k, y + k - 3, x + k, y + k - 3, Rgb{0, 150, 60});
    } else {
      c->Line(x - 4, y - 4, x + 4, y + 4, Rgb{210, 30, 30}, 3);
      c->Line(x - 4, y + 4, x + 4, y - 4, Rgb{210, 30, 30}, 3);
    }
  }
}

// Legend: stages, decisions.
void FeaturePlotLegend(int lx, int top, const std::map<std::string, size_t>& stages, Canvas* c) {
  const Rgb ink{0, 0, 0};
  int ly = top;
  c->Text(lx, ly, "stage of jump:", ink);
  ly += 20;
  for (const auto& [name, idx] : stages) {
    c->Disc(lx + 6, ly + 7, 4, ink);
    c->Disc(lx + 6, ly + 7, 3, kStageColours[idx % 8]);
    c->Text(lx + 16, ly, name.substr(0, 24), ink);
    ly += 18;
  }
  ly += 10;
  for (int k = 0; k < 6; ++k) c->Line(lx + 6 - k, ly + 4 + k, lx + 6 + k, ly + 4 + k, Rgb{0, 150, 60});
  c->Text(lx + 16, ly, "kept (decision)", ink);
  ly += 18;
  c->Line(lx + 2, ly + 3, lx + 10, ly + 11, Rgb{210, 30, 30}, 3);
  c->Line(lx + 2, ly + 11, lx + 10, ly + 3, Rgb{210, 30, 30}, 3);
  c->Text(lx + 16, ly, "rejected", ink);
}

}  // namespace

Canvas RenderFeaturePlot(const trace::FeatureHistory& h) {
  const int W = h.follow ? 1100 : 900, H = 440, left = 70, right = 230, top = 40, bottom = 90;
  Canvas c(W, H, Rgb{255, 255, 255});
  const Rgb ink{0, 0, 0};
  std::map<std::string, size_t> stages;
  const std::vector<Point> pts = FeaturePlotPoints(h, &stages);
  FeaturePlotArea area{left, top, W - left - right, H - top - bottom};
  FeaturePlotRange(h, pts, &area);
  size_t si = 0;
  for (auto& [name, idx] : stages) idx = si++;
  const std::string title =
      h.follow ? h.id + " followed (" + std::to_string(h.chain.size()) + " linked entities): p(dynamic) updates"
               : h.id + ": probability updates across frames";
  FeaturePlotAxes(area, H, title, &c);
  FeaturePlotSeries(area, pts, stages, &c);
  FeaturePlotDecisions(area, h, &c);
  FeaturePlotLegend(left + area.pw + 16, top, stages, &c);
  if (pts.empty()) c.Text(left + 20, top + 20, "no probability updates for " + h.id, ink);
  return c;
}

void WriteFeaturePlot(const trace::FeatureHistory& history, const std::string& png_path) {
  RenderFeaturePlot(history).WritePng(png_path);
}

}  // namespace dynref::render
