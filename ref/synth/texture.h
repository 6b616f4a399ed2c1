// Procedural, seeded surface textures for the synthetic office (albedo in linear [0,1] RGB).
// Every pattern is a pure function of (material, u, v) with (u, v) in metres on the surface,
// so texture is fixed to the surface (trackable) and identical in every frame and sub-frame.
// Pattern randomness comes from integer hashes keyed by a per-material seed that the scene
// draws from Rng(seed, "synth.scene") -- no per-pixel RNG state.
#pragma once
#include <cstdint>
#include <vector>

namespace dynref::synth {

struct Rgb {
  float r = 0, g = 0, b = 0;
};
inline Rgb operator+(Rgb a, Rgb b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline Rgb operator*(Rgb a, float s) { return {a.r * s, a.g * s, a.b * s}; }
inline Rgb Mix(Rgb a, Rgb b, float t) { return a * (1 - t) + b * t; }

enum class Pattern : uint8_t {
  kFlat,        // c0 with faint noise
  kCarpet,      // tiles of `scale` m, speckle and blotches
  kWood,        // grain along u
  kFabric,      // fine woven noise (cubicle partitions)
  kPaint,       // wall paint with faint mottling
  kCeiling,     // acoustic tiles of `scale` m with grid
  kLight,       // emissive panel
  kPrint,       // posters, screens, papers, book covers, clothing prints: blocks, text lines, dots
  kWhiteboard,  // white with marker strokes
  kSpines,      // rows of book/binder spines with labels
  kKeyboard,    // key grid
  kStripes,     // clothing: bands along v of width `scale`
  kChecks,      // clothing: plaid of period `scale`
  kDenim,       // clothing: twill noise
  kSkin,        // skin with face features near the +x side of a head (eyes, mouth)
  kHair,
  kCardboard,   // box with tape and printed labels
  kMetal,       // brushed metal
};

struct Material {
  Pattern pattern = Pattern::kFlat;
  Rgb c0, c1, c2;         // base, secondary, accent colours
  float scale = 0.1f;     // pattern period in metres
  uint32_t seed = 1;
  float emission = 0.f;   // radiance added regardless of lighting (light panels, screens)
};

Rgb Albedo(const Material& m, float u, float v);

// Integer hash helpers (also used by the sensor model for per-pixel decisions).
uint32_t Hash3(int32_t x, int32_t y, uint32_t seed);
float Hash01(int32_t x, int32_t y, uint32_t seed);
float ValueNoise(float x, float y, uint32_t seed);  // smooth, [0,1)

}  // namespace dynref::synth
