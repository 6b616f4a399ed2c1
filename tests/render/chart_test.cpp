// render/chart: bars and lines land where their values say, missing values draw nothing, and
// degenerate inputs (no data, one point, zero on a log axis) give a plot instead of a crash.
#include <catch2/catch.hpp>
#include <cmath>

#include "render/chart.h"

using namespace dynref::render;

namespace {

bool Same(Rgb a, Rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// Number of pixels of colour c in column x.
int CountInColumn(const Canvas& img, int x, Rgb c) {
  int n = 0;
  for (int y = 0; y < img.height(); ++y) n += Same(img.Get(x, y), c);
  return n;
}

}  // namespace

TEST_CASE("chart: bar heights follow the values, NaN draws no bar") {
  const Rgb red{200, 0, 0};
  BarChartOptions o;
  o.width = 500, o.height = 300;
  // Plot area: x 80..250 (right margin 250), two groups of 85 px, one bar each, 69 px wide.
  const Canvas c = RenderBarChart({"a", "b", "c"}, {{"s", {1.0, 2.0, std::nan("")}, {}, red}}, o);
  const int gw = (500 - 80 - 250) / 3;
  const int h1 = CountInColumn(c, 80 + gw / 2, red), h2 = CountInColumn(c, 80 + gw + gw / 2, red);
  CHECK(h1 > 20);
  CHECK(std::abs(h2 - 2 * h1) <= 3);  // twice the value, twice the height (bars start at 0)
  CHECK(CountInColumn(c, 80 + 2 * gw + gw / 2, red) == 0);
}

TEST_CASE("chart: degenerate inputs still give a plot") {
  BarChartOptions lo;
  lo.log_y = true;
  const Canvas a = RenderBarChart({"x"}, {{"s", {0.0}, {}, Rgb{1, 2, 3}}}, lo);  // zero on a log axis: no bar
  CHECK(a.width() == lo.width);
  const Canvas b = RenderBarChart({}, {}, BarChartOptions{});
  CHECK(b.height() == BarChartOptions{}.height);
  LineChartOptions o;
  o.equal_aspect = true;
  const Canvas c = RenderLineChart({{"one", {1.0}, {2.0}, Rgb{0, 0, 255}, 1},
                                    {"gap", {0.0, 1.0, 2.0}, {0.0, std::nan(""), 1.0}, Rgb{0, 255, 0}, 1}},
                                   o);
  CHECK(c.width() == o.width);
  const Canvas d = RenderLineChart({}, LineChartOptions{});
  CHECK(d.height() == LineChartOptions{}.height);
}

TEST_CASE("chart: ticks are 1-2-5 steps and print their decimals") {
  CHECK(NiceStep(1.0, 5) == Approx(0.2));
  CHECK(NiceStep(0.03, 6) == Approx(0.005));
  CHECK(NiceStep(700, 8) == Approx(100));
  CHECK(TickText(0.25, 0.05) == "0.25");
  CHECK(TickText(300, 100) == "300");
}
