#include <catch2/catch.hpp>
#include <cmath>

#include "core/rng.h"

using dynref::Rng;

TEST_CASE("rng: same seed and stream give the same sequence, other streams differ") {
  Rng a(42, "sgdo.F"), b(42, "sgdo.F"), c(42, "synth.people"), d(43, "sgdo.F");
  bool differs_c = false, differs_d = false;
  for (int i = 0; i < 100; ++i) {
    const uint64_t va = a.NextU64();
    REQUIRE(va == b.NextU64());
    differs_c |= va != c.NextU64();
    differs_d |= va != d.NextU64();
  }
  CHECK(differs_c);
  CHECK(differs_d);
}

TEST_CASE("rng: first outputs are pinned (platform-independent generator)") {
  // Golden values: a change here changes every RANSAC and every synthetic sequence.
  // Values from xoshiro256** seeded by SplitMix64(seed ^ FNV-1a(name)), cross-checked against
  // an independent Python implementation of rng.h's description.
  Rng r(0, "");
  CHECK(r.NextU64() == 0x21382ef092ed7068ULL);
  CHECK(r.NextU64() == 0x5b54c052757adf62ULL);
  CHECK(r.NextU64() == 0xa64cb2cf68795072ULL);
  CHECK(r.NextU64() == 0xd35c15d5962035afULL);
  Rng named(0, "sgdo.F");
  CHECK(named.NextU64() == 0x1faa00f9a1464d85ULL);
  Rng u(7, "test");
  double sum = 0;
  for (int i = 0; i < 10000; ++i) sum += u.Uniform01();
  CHECK(std::abs(sum / 10000 - 0.5) < 0.02);
}

TEST_CASE("rng: UniformInt stays in range and hits both ends") {
  Rng r(1, "int");
  bool lo = false, hi = false;
  for (int i = 0; i < 2000; ++i) {
    const int64_t v = r.UniformInt(-3, 3);
    REQUIRE(v >= -3);
    REQUIRE(v <= 3);
    lo |= v == -3;
    hi |= v == 3;
  }
  CHECK(lo);
  CHECK(hi);
  CHECK(r.UniformInt(5, 5) == 5);
  CHECK_THROWS(r.UniformInt(2, 1));
}

TEST_CASE("rng: Gaussian has unit variance") {
  Rng r(3, "gauss");
  double s = 0, s2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double g = r.Gaussian();
    s += g;
    s2 += g * g;
  }
  CHECK(std::abs(s / n) < 0.03);
  CHECK(std::abs(s2 / n - 1.0) < 0.05);
}
