#include <catch2/catch.hpp>

#include <limits>
#include <stdexcept>
#include <utility>

#include "core/rng.h"
#include "dense/filters.h"
#include "dense/voxel_bricks.h"

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

TEST_CASE("dense voxel: key index keeps insertion order through growth, negative keys, absent keys") {
  VoxelKeyIndex index;
  std::vector<VoxelKey> keys;
  for (int64_t i = 0; i < 5000; ++i) keys.push_back({i % 17 - 8, -i, (i * 7919) % 101 - 50});
  for (size_t i = 0; i < keys.size(); ++i) CHECK(index.Insert(keys[i]) == i);
  REQUIRE(index.size() == keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    CHECK(index.Find(keys[i]) == i);
    CHECK(index.Insert(keys[i]) == i);  // present: same index, nothing added
    CHECK(index.key(static_cast<uint32_t>(i)) == keys[i]);
  }
  CHECK(index.size() == keys.size());
  CHECK(index.Find({0, 1, 0}) == VoxelKeyIndex::kNone);
  CHECK(VoxelKeyIndex().Find({0, 0, 0}) == VoxelKeyIndex::kNone);
}

TEST_CASE("dense voxel: majority class over more distinct classes than the inline votes hold") {
  // One voxel, classes 9 x2, 4 x1, 7 x2, -1 x1, 2 x2, 11 x1: three classes tie at 2, the smallest (2) wins.
  PointCloud in;
  for (int16_t c : {9, 4, 9, 7, -1, 2, 7, 11, 2}) in.push_back(P(0.001f, 0.002f, 0.003f, 0, c));
  REQUIRE(VoxelDownsample(in, 0.01).size() == 1);
  CHECK(VoxelDownsample(in, 0.01)[0].class_id == 2);
  in.push_back(P(0.001f, 0.002f, 0.003f, 0, 11));
  in.push_back(P(0.001f, 0.002f, 0.003f, 0, 11));  // 11 now has 3 votes (two of them overflow)
  CHECK(VoxelDownsample(in, 0.01)[0].class_id == 11);
}

TEST_CASE("dense voxel: sorted voxelisation (radix or stable-sort fallback) equals the hashed grid bit for bit") {
  dynref::Rng rng(4, "test.dense.sort");
  const auto u = [&](double lo, double hi) { return static_cast<float>(lo + (hi - lo) * rng.UniformInt(0, 1 << 20) / double(1 << 20)); };
  for (const double span : {1.0, 1e6}) {  // 1e6 m at a 1 um leaf: 41 bits per axis, no packing
    const double leaf = span > 10 ? 1e-6 : 0.01;
    PointCloud in;
    for (int i = 0; i < 20000; ++i) {
      ColoredPoint p = P(u(-span, span), u(-span, span), u(-span, span), static_cast<uint8_t>(i % 251),
                         static_cast<int16_t>(i % 5 - 1));
      if (i % 3 == 0 && !in.empty()) p.x = in[static_cast<size_t>(i / 2)].x, p.y = in[static_cast<size_t>(i / 2)].y,
                                     p.z = in[static_cast<size_t>(i / 2)].z;  // shared voxels
      in.push_back(p);
    }
    in.push_back(P(std::numeric_limits<float>::quiet_NaN(), 0, 0));
    VoxelGrid grid(leaf);
    grid.Add(in);
    const PointCloud hashed = grid.Cloud();
    const PointCloud sorted = VoxelDownsample(in, leaf);
    const SortedVoxels voxels = SortIntoVoxels(in, leaf);
    REQUIRE(sorted.size() == hashed.size());
    REQUIRE(voxels.keys == grid.Keys());
    for (size_t i = 0; i < sorted.size(); ++i) {
      CHECK(sorted[i].x == hashed[i].x);
      CHECK(sorted[i].y == hashed[i].y);
      CHECK(sorted[i].z == hashed[i].z);
      CHECK(sorted[i].r == hashed[i].r);
      CHECK(sorted[i].class_id == hashed[i].class_id);
    }
  }
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

TEST_CASE("dense SOR: the brick look-up gives the k-d tree's capped statistic bit for bit") {
  // A noisy surface patch (dense: the k-th neighbour lies within the cap) plus scattered points
  // (sparse: most neighbours beyond the cap), split into a "map" and "new" points.
  dynref::Rng rng(3, "test.dense.bricks");
  const auto u = [&](double lo, double hi) { return static_cast<float>(lo + (hi - lo) * rng.UniformInt(0, 1 << 20) / double(1 << 20)); };
  PointCloud map, fresh;
  for (int i = 0; i < 3000; ++i) {
    const ColoredPoint p = i % 10 == 0 ? P(u(-0.5, 0.5), u(-0.5, 0.5), u(1.0, 2.0)) : P(u(-0.2, 0.2), u(-0.2, 0.2), u(1.49, 1.51));
    (i % 3 == 0 ? fresh : map).push_back(p);
  }
  const double leaf = 0.01, cap = 0.04;
  const int k = 20;
  const std::vector<double> tree = MeanKnnDistances(fresh, map, k, cap);
  REQUIRE(tree.size() == fresh.size());
  VoxelGrid keys(leaf);
  VoxelBricks map_bricks(leaf, cap), fresh_bricks(leaf, cap);
  for (const ColoredPoint& p : map) map_bricks.Add(keys.KeyOf(p), {p.x, p.y, p.z});
  for (const ColoredPoint& p : fresh) fresh_bricks.Add(keys.KeyOf(p), {p.x, p.y, p.z});
  const std::vector<double> bricks = CappedMeanKnnDistances(fresh_bricks, {&map_bricks}, k, cap);
  REQUIRE(bricks.size() == fresh.size());
  int capped = 0;
  for (size_t i = 0; i < fresh.size(); ++i) {
    CHECK(bricks[i] == tree[i]);
    capped += bricks[i] > 0.999 * cap;
  }
  CHECK(capped > 10);  // isolated points: every neighbour counted at the cap
  // Uncapped statistic of the same points is larger for the isolated ones only.
  const std::vector<double> plain = MeanKnnDistances(fresh, map, k);
  for (size_t i = 0; i < fresh.size(); ++i) CHECK(plain[i] >= tree[i]);
  CHECK_THROWS_AS(MeanKnnDistances(fresh, map, k, 0.0), std::invalid_argument);
  // --threads (issue 18): bricks side by side, the same values for 2, 3 and 4 threads.
  for (int threads : {2, 3, 4}) CHECK(CappedMeanKnnDistances(fresh_bricks, {&map_bricks}, k, cap, threads) == bricks);
  const VoxelBricks other_size(leaf, 2 * cap);
  CHECK_THROWS_AS(CappedMeanKnnDistances(fresh_bricks, {&other_size}, k, cap), std::invalid_argument);
}
