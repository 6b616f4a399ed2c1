// Seeded, platform-independent random numbers with named streams.
// Never use std::*_distribution: their output differs between standard libraries.
// Generator: xoshiro256** (Blackman & Vigna 2018), seeded through SplitMix64 from
// (seed, FNV-1a hash of the stream name), so "sgdo.F" and "synth.people" never share draws.
#pragma once
#include <cstdint>
#include <string>

namespace dynref {

class Rng {
 public:
  Rng(uint64_t seed, const std::string& stream_name);

  uint64_t NextU64();
  // Unbiased integer in [lo, hi] (inclusive), by rejection sampling. Requires lo <= hi.
  int64_t UniformInt(int64_t lo, int64_t hi);
  // Double in [0, 1) with 53 random mantissa bits.
  double Uniform01();
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform01(); }
  // Standard normal by Box-Muller (two uniforms per call, no cached state).
  double Gaussian();
  double Gaussian(double mean, double sigma) { return mean + sigma * Gaussian(); }
  bool Bernoulli(double p) { return Uniform01() < p; }

 private:
  uint64_t s_[4];
};

// 64-bit FNV-1a of a byte string (stream names, descriptor hashes).
uint64_t Fnv1a64(const void* data, size_t size, uint64_t basis = 0xcbf29ce484222325ULL);
inline uint64_t Fnv1a64(const std::string& s) { return Fnv1a64(s.data(), s.size()); }

}  // namespace dynref
