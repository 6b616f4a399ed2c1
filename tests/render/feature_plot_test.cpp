// `trace feature --plot` (ref/render/feature_plot): with --follow the chain's p(dynamic) jumps are
// drawn in stage colours over the chain's frames, carriers (structure, match.*, "<id>@...") are not
// drawn, decisions are marked under the axis; the same history renders the same pixels.
#include <catch2/catch.hpp>

#include "../trace/trace_follow_sample.h"
#include "render/feature_plot.h"
#include "test_support.h"

using namespace dynref;

namespace {
int CountColour(const render::Canvas& c, render::Rgb col) {
  int n = 0;
  for (int y = 0; y < c.height(); ++y)
    for (int x = 0; x < c.width(); ++x) {
      const render::Rgb p = c.Get(x, y);
      n += p.r == col.r && p.g == col.g && p.b == col.b;
    }
  return n;
}
}  // namespace

TEST_CASE("feature plot --follow: chain jumps, stage legend, a rejected decision, deterministic pixels") {
  const std::string path = test::ScratchDir("feature_plot_follow") + "/follow.dtr";
  test::WriteFollowTrace(path);
  trace::TraceReader reader(path);
  const trace::FeatureHistory h = trace::CollectFollowHistory(reader, "f3.13");
  const render::Canvas c = render::RenderFeaturePlot(h);
  CHECK(c.width() == 1100);
  // Two stages (mgd.inherit, mgd.smooth): the first two legend colours appear, the third does not.
  CHECK(CountColour(c, {230, 159, 0}) > 20);
  CHECK(CountColour(c, {86, 180, 233}) > 20);
  CHECK(CountColour(c, {0, 158, 115}) == 0);
  CHECK(CountColour(c, {210, 30, 30}) > 10);  // the rejected f5.15 (and the legend's cross)
  const render::Canvas again = render::RenderFeaturePlot(trace::CollectFollowHistory(reader, "f3.13"));
  bool same = true;
  for (int y = 0; y < c.height() && same; ++y)
    for (int x = 0; x < c.width() && same; ++x) {
      const render::Rgb a = c.Get(x, y), b = again.Get(x, y);
      same = a.r == b.r && a.g == b.g && a.b == b.b;
    }
  CHECK(same);
  // Line chain: only a structure record (carrier, not drawn) and mgd.inherit updates.
  const render::Canvas lines = render::RenderFeaturePlot(trace::CollectFollowHistory(reader, "l3.2"));
  CHECK(CountColour(lines, {230, 159, 0}) > 20);
  CHECK(CountColour(lines, {86, 180, 233}) == 0);
}
