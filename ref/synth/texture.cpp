#include "synth/texture.h"

#include <cmath>

namespace dynref::synth {

uint32_t Hash3(int32_t x, int32_t y, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B9u ^ uint32_t(x) * 0x85EBCA6Bu;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= uint32_t(y) * 0xC2B2AE35u;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

float Hash01(int32_t x, int32_t y, uint32_t seed) { return float(Hash3(x, y, seed) >> 8) * (1.f / 16777216.f); }

float ValueNoise(float x, float y, uint32_t seed) {
  const float fx = std::floor(x), fy = std::floor(y);
  const int32_t ix = int32_t(fx), iy = int32_t(fy);
  float tx = x - fx, ty = y - fy;
  tx = tx * tx * (3 - 2 * tx);
  ty = ty * ty * (3 - 2 * ty);
  const float a = Hash01(ix, iy, seed), b = Hash01(ix + 1, iy, seed);
  const float c = Hash01(ix, iy + 1, seed), d = Hash01(ix + 1, iy + 1, seed);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

namespace {

inline float FracF(float x) { return x - std::floor(x); }

Rgb Palette(uint32_t h) {
  // Saturated print colours; one of a few families so posters look designed, not noise.
  static const Rgb kColours[10] = {{0.75f, 0.12f, 0.10f}, {0.10f, 0.30f, 0.70f}, {0.95f, 0.75f, 0.10f},
                                   {0.12f, 0.55f, 0.25f}, {0.08f, 0.08f, 0.10f}, {0.90f, 0.45f, 0.10f},
                                   {0.45f, 0.15f, 0.55f}, {0.10f, 0.60f, 0.65f}, {0.85f, 0.85f, 0.82f},
                                   {0.55f, 0.35f, 0.20f}};
  return kColours[h % 10];
}

Rgb Print(const Material& m, float u, float v) {
  const float s = m.scale;
  const float cu = u / s, cv = v / s;
  const int32_t iu = int32_t(std::floor(cu)), iv = int32_t(std::floor(cv));
  const float fu = cu - float(iu), fv = cv - float(iv);
  const uint32_t h = Hash3(iu, iv, m.seed);
  const Rgb bg = m.c0;
  switch (h % 6) {
    case 0: {  // solid block with margin
      if (fu > 0.08f && fu < 0.92f && fv > 0.08f && fv < 0.92f) return Palette(h >> 8);
      return bg;
    }
    case 1:
    case 2: {  // text lines: words of varying length on rows
      const float rows = 5.f;
      const int32_t row = int32_t(fv * rows);
      const float rf = fv * rows - float(row);
      if (rf < 0.35f || rf > 0.75f || fu < 0.06f || fu > 0.94f) return bg;
      const float wu = fu * 7.f;
      const int32_t word = int32_t(wu);
      const uint32_t hw = Hash3(iu * 16 + word, iv * 8 + row, m.seed ^ 0xABCDu);
      if ((hw & 3u) == 0 || FracF(wu) > 0.8f) return bg;
      return (hw & 16u) ? m.c1 : Palette(h >> 12) * 0.6f;
    }
    case 3: {  // disc with ring
      const float du = fu - 0.5f, dv = fv - 0.5f, r2 = du * du + dv * dv;
      if (r2 < 0.09f) return Palette(h >> 8);
      if (r2 < 0.13f) return m.c1;
      return bg;
    }
    case 4: {  // photo-like blobs
      const float n = ValueNoise(u / (s * 0.3f), v / (s * 0.3f), h);
      return Mix(Palette(h >> 8), Palette(h >> 16), n > 0.5f ? 1.f : 0.f) * (0.7f + 0.3f * n);
    }
    default: {  // dots
      const float du = FracF(fu * 4) - 0.5f, dv = FracF(fv * 4) - 0.5f;
      return (du * du + dv * dv < 0.06f) ? m.c2 : bg;
    }
  }
}

Rgb AlbedoCarpet(const Material& m, float u, float v) {
  const int32_t tu = int32_t(std::floor(u / m.scale)), tv = int32_t(std::floor(v / m.scale));
  Rgb c = Mix(m.c0, m.c1, Hash01(tu, tv, m.seed) < 0.5f ? 0.f : 0.6f);
  const float speck = Hash01(int32_t(std::floor(u * 90)), int32_t(std::floor(v * 90)), m.seed + 1);
  const float blot = ValueNoise(u * 6, v * 6, m.seed + 2);
  c = c * (0.55f + 0.7f * speck) * (0.8f + 0.4f * blot);
  if (FracF(u / m.scale) < 0.01f || FracF(v / m.scale) < 0.01f) c = c * 0.5f;
  return c;
}

Rgb AlbedoWood(const Material& m, float u, float v) {
  const float t = v * 45.f + 6.f * ValueNoise(u * 3.f, v * 10.f, m.seed);
  const float g = 0.5f + 0.5f * std::sin(t);
  const float knot = ValueNoise(u * 12.f, v * 30.f, m.seed + 5);
  return Mix(m.c0, m.c1, g * g * g) * (0.8f + 0.35f * knot);
}

Rgb AlbedoCeiling(const Material& m, float u, float v) {
  const float fu = FracF(u / m.scale), fv = FracF(v / m.scale);
  if (fu < 0.03f || fv < 0.03f) return m.c1;
  const float p = Hash01(int32_t(std::floor(u * 120)), int32_t(std::floor(v * 120)), m.seed);
  return m.c0 * (0.85f + 0.2f * p);
}

Rgb AlbedoWhiteboard(const Material& m, float u, float v) {
  const int32_t row = int32_t(std::floor(v / 0.07f));
  const uint32_t h = Hash3(row, 0, m.seed);
  const float x0 = float(h & 255u) / 255.f * 0.8f, len = 0.2f + float((h >> 8) & 255u) / 255.f * 0.9f;
  const float off = FracF(v / 0.07f) - 0.5f - 0.18f * std::sin(u * 37.f + float(h & 7u));
  if ((h >> 20) % 3 != 0 && u > x0 && u < x0 + len && std::fabs(off) < 0.09f)
    return (h >> 24) & 1u ? m.c1 : m.c2;
  return m.c0 * (0.96f + 0.04f * ValueNoise(u * 5, v * 5, m.seed));
}

Rgb AlbedoSpines(const Material& m, float u, float v) {
  const float cu = u / m.scale;
  const int32_t i = int32_t(std::floor(cu));
  const float f = cu - float(i);
  const uint32_t h = Hash3(i, 0, m.seed);
  if (f < 0.07f) return Palette(h) * 0.25f;
  const float height = 0.75f + 0.25f * float((h >> 4) & 255u) / 255.f;
  if (v > height * 0.24f) return m.c0;  // gap above shorter books
  Rgb c = Palette(h >> 8);
  const float band = v / 0.24f;
  if (band > 0.55f && band < 0.7f) c = m.c1;
  if (band > 0.15f && band < 0.2f) c = m.c2;
  return c;
}

Rgb AlbedoKeyboard(const Material& m, float u, float v) {
  const float ku = FracF(u / 0.019f), kv = FracF(v / 0.019f);
  if (ku < 0.14f || kv < 0.14f) return m.c1;
  const uint32_t h = Hash3(int32_t(std::floor(u / 0.019f)), int32_t(std::floor(v / 0.019f)), m.seed);
  if (std::fabs(ku - 0.57f) < 0.13f && std::fabs(kv - 0.57f) < 0.16f && (h & 1u)) return m.c2;
  return m.c0;
}

Rgb AlbedoStripes(const Material& m, float u, float v) {
  const int32_t band = int32_t(std::floor(v / m.scale));
  const bool odd = (band & 1) != 0;
  if (!odd) return m.c0 * (0.9f + 0.1f * ValueNoise(u * 30, v * 30, m.seed));
  const float f = FracF(u / (m.scale * 1.6f));
  if (Hash01(band, 7, m.seed) < 0.5f && f < 0.45f) return m.c2;
  return m.c1;
}

Rgb AlbedoChecks(const Material& m, float u, float v) {
  const float fu = FracF(u / m.scale), fv = FracF(v / m.scale);
  const bool a = fu < 0.5f, b = fv < 0.5f;
  Rgb c = (a && b) ? m.c1 : ((a || b) ? Mix(m.c0, m.c1, 0.45f) : m.c0);
  if (std::fabs(fu - 0.75f) < 0.04f || std::fabs(fv - 0.75f) < 0.04f) c = m.c2;
  return c;
}

Rgb AlbedoDenim(const Material& m, float u, float v) {
  const float tw = Hash01(int32_t(std::floor((u + v) * 300)), int32_t(std::floor((u - v) * 60)), m.seed);
  const float fade = ValueNoise(u * 9, v * 4, m.seed + 1);
  Rgb c = Mix(m.c0, m.c1, 0.6f * fade) * (0.8f + 0.3f * tw);
  if (FracF(v / m.scale) < 0.04f) c = m.c2;  // seams/pockets at a coarse period
  return c;
}

Rgb AlbedoSkin(const Material& m, float u, float v) {
  float du = std::fmod(u, m.scale);
  if (du > 0.5f * m.scale) du -= m.scale;
  const float ex = std::fabs(du) - 0.033f, ey = v - 0.15f;
  if (ex * ex / 0.00012f + ey * ey / 0.00005f < 1.f) return m.c2;            // eyes
  if (std::fabs(du) < 0.05f && std::fabs(v - 0.133f) < 0.005f && std::fabs(du) > 0.015f)
    return m.c1 * 0.6f;                                                       // brows
  if (std::fabs(du) < 0.024f && std::fabs(v - 0.245f) < 0.006f) return {0.55f, 0.18f, 0.16f};  // mouth
  return m.c0 * (0.92f + 0.1f * ValueNoise(u * 40, v * 40, m.seed));
}

Rgb AlbedoCardboard(const Material& m, float u, float v) {
  Rgb c = m.c0 * (0.85f + 0.25f * ValueNoise(u * 15, v * 15, m.seed));
  const float fv = FracF(v / m.scale), fu = FracF(u / m.scale);
  if (std::fabs(fv - 0.5f) < 0.07f) c = m.c1;
  if (fu > 0.1f && fu < 0.4f && fv > 0.65f && fv < 0.9f) {
    const int32_t row = int32_t((fv - 0.65f) / 0.05f);
    c = (FracF((fv - 0.65f) / 0.05f) < 0.5f && Hash01(int32_t(fu * 20), row, m.seed) < 0.7f) ? m.c2
                                                                                         : Rgb{0.9f, 0.9f, 0.88f};
  }
  return c;
}

}  // namespace

Rgb Albedo(const Material& m, float u, float v) {
  switch (m.pattern) {
    case Pattern::kFlat:
      return m.c0 * (0.95f + 0.1f * ValueNoise(u * 20, v * 20, m.seed));
    case Pattern::kCarpet:
      return AlbedoCarpet(m, u, v);
    case Pattern::kWood:
      return AlbedoWood(m, u, v);
    case Pattern::kFabric: {
      const float n = Hash01(int32_t(std::floor(u * 250)), int32_t(std::floor(v * 250)), m.seed);
      return m.c0 * (0.8f + 0.25f * n + 0.2f * ValueNoise(u * 8, v * 8, m.seed + 1));
    }
    case Pattern::kPaint:
      return m.c0 * (0.9f + 0.1f * ValueNoise(u * 3, v * 3, m.seed) + 0.05f * ValueNoise(u * 40, v * 40, m.seed + 3));
    case Pattern::kCeiling:
      return AlbedoCeiling(m, u, v);
    case Pattern::kLight: {
      const float fu = FracF(u / m.scale), fv = FracF(v / m.scale);
      return (fu < 0.04f || fv < 0.04f) ? m.c1 : m.c0;
    }
    case Pattern::kPrint:
      return Print(m, u, v);
    case Pattern::kWhiteboard:
      return AlbedoWhiteboard(m, u, v);
    case Pattern::kSpines:
      return AlbedoSpines(m, u, v);
    case Pattern::kKeyboard:
      return AlbedoKeyboard(m, u, v);
    case Pattern::kStripes:
      return AlbedoStripes(m, u, v);
    case Pattern::kChecks:
      return AlbedoChecks(m, u, v);
    case Pattern::kDenim:
      return AlbedoDenim(m, u, v);
    case Pattern::kSkin:
      return AlbedoSkin(m, u, v);
    case Pattern::kHair:
      return m.c0 * (0.7f + 0.6f * Hash01(int32_t(std::floor(u * 300)), int32_t(std::floor(v * 30)), m.seed));
    case Pattern::kCardboard:
      return AlbedoCardboard(m, u, v);
    case Pattern::kMetal:
      return m.c0 * (0.85f + 0.2f * Hash01(int32_t(std::floor(u * 500)), int32_t(std::floor(v * 20)), m.seed));
  }
  return m.c0;
}

}  // namespace dynref::synth
