#include "synth/sensor.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dynref::synth {
namespace {

constexpr int kGaussBits = 12;
constexpr int kGaussSize = 1 << kGaussBits;

const std::array<float, kGaussSize>& GaussTable() {
  static const std::array<float, kGaussSize> table = [] {
    std::array<float, kGaussSize> t{};
    for (int i = 0; i < kGaussSize; ++i) {
      const double p = (double(i) + 0.5) / double(kGaussSize);
      double lo = -8, hi = 8;  // bisection on Phi(x) = 0.5 erfc(-x / sqrt 2)
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p) lo = mid; else hi = mid;
      }
      t[size_t(i)] = float(0.5 * (lo + hi));
    }
    return t;
  }();
  return table;
}

// Linear [0, 1] -> sRGB-like gamma 1/2.2, 8-bit scale, via a 4096 LUT (no pow per pixel).
const std::array<float, 4097>& GammaLut() {
  static const std::array<float, 4097> lut = [] {
    std::array<float, 4097> t{};
    for (int i = 0; i <= 4096; ++i) t[size_t(i)] = float(255.0 * std::pow(double(i) / 4096.0, 1.0 / 2.2));
    return t;
  }();
  return lut;
}

// Draws standard normals four at a time from one 64-bit word.
class GaussStream {
 public:
  explicit GaussStream(Rng& rng) : rng_(rng) {}
  float Next() {
    if (left_ == 0) {
      word_ = rng_.NextU64();
      left_ = 4;
    }
    const uint32_t bits = uint32_t(word_ >> 52);  // top 12 bits
    word_ <<= 16;
    --left_;
    return GaussTable()[bits];
  }

 private:
  Rng& rng_;
  uint64_t word_ = 0;
  int left_ = 0;
};

}  // namespace

double TableGaussian(uint32_t bits12) { return GaussTable()[bits12 & (kGaussSize - 1)]; }

void ShadeRadiance(const Scene& scene, const Intrinsics& K, const SE3& T_wc, const GBuffer& gb, cv::Mat* radiance) {
  radiance->create(gb.height, gb.width, CV_32FC3);
  const Eigen::Matrix3f R = T_wc.linear().cast<float>();
  const Eigen::Vector3f t = T_wc.translation().cast<float>();
  const float ifx = 1.f / K.fx, ify = 1.f / K.fy;
  constexpr float kAmbient = 0.2f;
  for (int y = 0; y < gb.height; ++y) {
    float* out = radiance->ptr<float>(y);
    for (int x = 0; x < gb.width; ++x) {
      const int idx = y * gb.width + x;
      const int32_t f = gb.face[size_t(idx)];
      if (f < 0) {
        out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = 0.f;
        continue;
      }
      const FaceRecord& rec = gb.faces[size_t(f)];
      const Material& m = scene.materials[rec.material];
      const Rgb a = Albedo(m, gb.u[size_t(idx)], gb.v[size_t(idx)]);
      const float z = gb.z[size_t(idx)];
      const Eigen::Vector3f p_w = R * Eigen::Vector3f((float(x) - K.cx) * ifx * z, (float(y) - K.cy) * ify * z, z) + t;
      float light = kAmbient;
      for (const Light& L : scene.lights) {
        const Eigen::Vector3f d = L.pos_w - p_w;
        const float d2 = d.squaredNorm();
        const float ndl = rec.n_w.dot(d) / std::sqrt(d2);
        if (ndl > 0) light += L.intensity * ndl * 1.05f / (0.8f + d2);
      }
      const float k = light + m.emission;
      out[3 * x] = a.b * k * 0.86f;  // warm fluorescent/tungsten mix
      out[3 * x + 1] = a.g * k * 0.95f;
      out[3 * x + 2] = a.r * k;
    }
  }
}

cv::Mat SenseRgb(const SensorModel& s, const cv::Mat& radiance, bool low_light, Rng& rng) {
  cv::Mat out(radiance.rows, radiance.cols, CV_8UC3);
  GaussStream g(rng);
  const auto& lut = GammaLut();
  const float cx = 0.5f * float(radiance.cols), cy = 0.5f * float(radiance.rows);
  const float inv_r2 = 1.f / (cx * cx + cy * cy);
  const float exposure = low_light ? float(s.low_light_exposure) : float(s.exposure);
  const float read = float(low_light ? s.low_light_read_noise : s.read_noise);
  const float black = low_light ? float(s.low_light_black) : 0.f;
  const float contrast = low_light ? 0.75f : 1.f;  // low light: flatter tone curve
  for (int y = 0; y < radiance.rows; ++y) {
    const float* in = radiance.ptr<float>(y);
    uint8_t* o = out.ptr<uint8_t>(y);
    for (int x = 0; x < radiance.cols; ++x) {
      const float r2 = ((float(x) - cx) * (float(x) - cx) + (float(y) - cy) * (float(y) - cy)) * inv_r2;
      const float vig = (1.f - float(s.vignetting) * r2) * exposure;
      for (int c = 0; c < 3; ++c) {
        const float lin = std::min(1.f, std::max(0.f, in[3 * x + c] * vig));
        float v = lut[size_t(lin * 4096.f)];
        v = black + contrast * v;
        const float sigma = std::sqrt(read * read + float(s.shot_noise) * v);
        v += sigma * g.Next();
        o[3 * x + c] = uint8_t(std::min(255.f, std::max(0.f, std::floor(v + 0.5f))));
      }
    }
  }
  return out;
}

cv::Mat SenseDepth(const SensorModel& s, const GBuffer& gb, Rng& rng) {
  const int W = gb.width, H = gb.height;
  cv::Mat out(H, W, CV_16U, cv::Scalar(0));
  GaussStream g(rng);
  // Edge dropouts first (the far side of a depth discontinuity), on the true depth.
  std::vector<uint8_t> drop(size_t(W) * H, 0);
  for (int y = 1; y < H - 1; ++y) {
    for (int x = 1; x < W - 1; ++x) {
      const size_t i = size_t(y) * W + x;
      const float z = gb.z[i];
      if (!std::isfinite(z)) continue;
      const float thr = std::max(float(s.edge_abs_m), float(s.edge_rel) * z);
      const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const float zn = gb.z[size_t(y + dy[k]) * W + size_t(x + dx[k])];
        if (z - zn > thr) {  // neighbour is in front: this pixel is on the far side
          if (rng.Bernoulli(s.edge_drop_p1)) drop[i] = 1;
          const int x2 = x - dx[k], y2 = y - dy[k];
          if (rng.Bernoulli(s.edge_drop_p2)) drop[size_t(y2) * W + size_t(x2)] = 1;
          break;
        }
      }
    }
  }
  for (int y = 0; y < H; ++y) {
    uint16_t* o = out.ptr<uint16_t>(y);
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      const float z = gb.z[i];
      if (!std::isfinite(z) || drop[i]) continue;
      const double zn = double(z) + s.SigmaZ(double(z)) * double(g.Next());
      if (zn > s.max_depth_m || zn < s.min_depth_m) continue;
      o[x] = uint16_t(std::min(65535.0, std::floor(zn * s.depth_factor + 0.5)));
    }
  }
  return out;
}

}  // namespace dynref::synth
