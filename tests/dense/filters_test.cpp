#include <catch2/catch.hpp>

#include <stdexcept>
#include <utility>

#include "core/rng.h"
#include "dense/filters.h"

using namespace dynref::dense;

namespace {
ColoredPoint P(float x, float y, float z, uint8_t r = 0, int16_t cls = -1) {
  ColoredPoint p;
  p.x = x, p.y = y, p.z = z, p.r = r, p.class_id = cls;
  return p;
}
}  // namespace

TEST_CASE("dense voxel: centroid, mean colour, majority class, key order") {
  const PointCloud in = {P(0.011f, 0, 0, 10, 3), P(0.019f, 0, 0, 20, 5), P(0.015f, 0, 0, 31, 5),
                         P(-0.005f, 0, 0, 100), P(0.001f, 0.5f, 0, 7)};
  const PointCloud out = VoxelDownsample(in, 0.01);
  REQUIRE(out.size() == 3);
  // Ordered by voxel key: (-1,0,0), (1,0,0), (0,50,0) sorts after (1,0,0)? No: x first.
  CHECK(out[0].x == Approx(-0.005f));
  CHECK(out[1].y == Approx(0.5f));  // key (0, 50, 0)
  CHECK(out[2].x == Approx(0.015f));
  CHECK(out[2].r == 20);            // round(61/3)
  CHECK(out[2].class_id == 5);
  CHECK(out[0].class_id == -1);
  CHECK_THROWS_AS(VoxelDownsample(in, 0.0), std::invalid_argument);
}

TEST_CASE("dense voxel: result does not depend on a permutation of equal-voxel inputs' order") {
  // Coordinates on a 2^-20 m grid in [0, 1]: voxel sums are exact in double, so the
  // summation-order caveat of VoxelDownsample does not apply and equality is bit-exact.
  PointCloud a;
  dynref::Rng rng(1, "test.dense");
  const auto coord = [&] { return static_cast<float>(rng.UniformInt(0, 1 << 20)) / (1 << 20); };
  for (int i = 0; i < 2000; ++i) {
    ColoredPoint p = P(coord(), coord(), coord(), static_cast<uint8_t>(rng.UniformInt(0, 255)),
                       static_cast<int16_t>(rng.UniformInt(-1, 2)));
    p.g = static_cast<uint8_t>(rng.UniformInt(0, 255));
    p.b = static_cast<uint8_t>(rng.UniformInt(0, 255));
    a.push_back(p);
  }
  // Deterministic Fisher-Yates shuffle of a copy.
  PointCloud shuffled = a;
  dynref::Rng shuffle_rng(2, "test.dense.shuffle");
  for (size_t i = shuffled.size() - 1; i > 0; --i) {
    const int64_t j = shuffle_rng.UniformInt(0, static_cast<int64_t>(i));
    std::swap(shuffled[i], shuffled[static_cast<size_t>(j)]);
  }
  // Output is ordered by voxel key, so no sorting is needed before comparing.
  const PointCloud out1 = VoxelDownsample(a, 0.1);
  const PointCloud out2 = VoxelDownsample(shuffled, 0.1);
  CHECK(!out1.empty());
  REQUIRE(out1.size() == out2.size());
  CHECK(out1.size() <= 1000);
  for (size_t i = 0; i < out1.size(); ++i) {
    INFO("voxel " << i);
    CHECK(out1[i].x == out2[i].x);
    CHECK(out1[i].y == out2[i].y);
    CHECK(out1[i].z == out2[i].z);
    CHECK(out1[i].r == out2[i].r);
    CHECK(out1[i].g == out2[i].g);
    CHECK(out1[i].b == out2[i].b);
    CHECK(out1[i].class_id == out2[i].class_id);
  }
}

TEST_CASE("dense SOR: removes isolated points, keeps a dense plane, keeps order") {
  PointCloud in;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 30; ++x) in.push_back(P(x * 0.01f, y * 0.01f, 1.0f));
  in.push_back(P(0.15f, 0.15f, 2.0f));   // far outlier
  in.push_back(P(-1.0f, 0.0f, 1.0f));    // far outlier
  SorOptions o;
  o.k = 8;
  o.std_mult = 1.0;
  const PointCloud out = StatisticalOutlierRemoval(in, o);
  CHECK(out.size() >= 880);
  CHECK(out.size() <= 900);
  for (const auto& p : out) CHECK(p.z == 1.0f);
  CHECK(out.front().x == in.front().x);
  // Fewer points than k: unchanged.
  const PointCloud small = {P(0, 0, 0), P(1, 1, 1)};
  CHECK(StatisticalOutlierRemoval(small, o).size() == 2);
  o.k = 0;
  CHECK_THROWS_WITH(o.Check(), Catch::Contains("k"));
}
