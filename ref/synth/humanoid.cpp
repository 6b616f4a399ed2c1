#include "synth/humanoid.h"

#include <cmath>

namespace dynref::synth {
namespace {

using Eigen::AngleAxisd;
using Eigen::Vector3d;
using Eigen::Vector3f;

SE3 Trans(double x, double y, double z) {
  SE3 T = SE3::Identity();
  T.translation() = Vector3d(x, y, z);
  return T;
}
SE3 Rot(double angle, const Vector3d& axis) {
  SE3 T = SE3::Identity();
  T.linear() = AngleAxisd(angle, axis).toRotationMatrix();
  return T;
}
SE3 Rx(double a) { return Rot(a, Vector3d::UnitX()); }
SE3 Ry(double a) { return Rot(a, Vector3d::UnitY()); }
SE3 Rz(double a) { return Rot(a, Vector3d::UnitZ()); }

Rgb RandomColour(Rng& rng, float lo, float hi) {
  return {float(rng.Uniform(lo, hi)), float(rng.Uniform(lo, hi)), float(rng.Uniform(lo, hi))};
}

int Add(std::vector<Material>* mats, const Material& m) {
  mats->push_back(m);
  return int(mats->size()) - 1;
}

// Body geometry (metres).
constexpr double kHipY = 0.095, kHipZ = -0.03, kThigh = 0.43, kShin = 0.43;
constexpr double kWaistZ = 0.10, kShoulderY = 0.21, kShoulderZ = 0.47, kNeckZ = 0.52;
constexpr double kUpperArm = 0.29, kForearm = 0.26;

}  // namespace

Humanoid::Humanoid(int instance, Rng& rng, std::vector<Material>* materials) : instance_(instance) {
  // Clothing: shirt with stripes / checks / print, trousers denim or plain, skin, hair, shoes.
  Material shirt;
  const int64_t kind = rng.UniformInt(0, 2);
  shirt.pattern = kind == 0 ? Pattern::kStripes : (kind == 1 ? Pattern::kChecks : Pattern::kPrint);
  shirt.c0 = RandomColour(rng, 0.6f, 0.95f);
  shirt.c1 = RandomColour(rng, 0.02f, 0.2f);
  shirt.c2 = RandomColour(rng, 0.2f, 0.9f);
  shirt.scale = float(kind == 2 ? rng.Uniform(0.06, 0.09) : rng.Uniform(0.035, 0.06));
  shirt.seed = uint32_t(rng.NextU64());
  if (kind == 2) shirt.c0 = shirt.c0 * 0.8f;
  const int m_shirt = Add(materials, shirt);
  Material pants;
  pants.pattern = rng.Bernoulli(0.6) ? Pattern::kDenim : Pattern::kChecks;
  pants.c0 = pants.pattern == Pattern::kDenim ? Rgb{0.10f, 0.16f, 0.35f} : RandomColour(rng, 0.3f, 0.6f);
  pants.c1 = pants.pattern == Pattern::kDenim ? Rgb{0.30f, 0.38f, 0.55f} : pants.c0 * 0.2f;
  pants.c2 = {0.6f, 0.45f, 0.2f};
  pants.scale = pants.pattern == Pattern::kDenim ? 0.12f : 0.06f;
  pants.seed = uint32_t(rng.NextU64());
  const int m_pants = Add(materials, pants);
  Material skin;
  skin.pattern = Pattern::kSkin;
  const float tone = float(rng.Uniform(0.35, 0.85));
  skin.c0 = {0.85f * tone + 0.1f, 0.62f * tone + 0.06f, 0.5f * tone + 0.04f};
  skin.c1 = {0.15f, 0.1f, 0.07f};
  skin.c2 = {0.05f, 0.04f, 0.04f};
  skin.scale = float(2 * 3.14159265358979 * 0.1);  // head circumference: eyes at u = 0 (+x)
  skin.seed = uint32_t(rng.NextU64());
  const int m_skin = Add(materials, skin);
  Material hair;
  hair.pattern = Pattern::kHair;
  hair.c0 = RandomColour(rng, 0.03f, 0.25f);
  hair.seed = uint32_t(rng.NextU64());
  const int m_hair = Add(materials, hair);
  Material shoes;
  shoes.pattern = Pattern::kFlat;
  shoes.c0 = RandomColour(rng, 0.03f, 0.15f);
  shoes.seed = uint32_t(rng.NextU64());
  const int m_shoes = Add(materials, shoes);
  Material hand = skin;
  hand.pattern = Pattern::kFlat;
  const int m_hand = Add(materials, hand);

  const int id = instance;
  meshes_[kPelvis].AddBox({-0.1f, -0.17f, -0.08f}, {0.1f, 0.17f, float(kWaistZ)}, m_pants, id);
  {
    Mesh torso;
    torso.AddLimb(0.52f, 0.2f, 0.18f, 8, m_shirt, id);
    Eigen::Affine3f T = Eigen::Affine3f::Identity();
    T.translate(Vector3f(0, 0, 0.52f));
    T.scale(Vector3f(0.6f, 1.0f, 1.0f));
    meshes_[kTorso].Append(torso, T);
  }
  {
    Mesh neck;
    neck.AddLimb(0.09f, 0.05f, 0.05f, 6, m_hand, id);
    Eigen::Affine3f T = Eigen::Affine3f::Identity();
    T.translate(Vector3f(0, 0, 0.08f));
    meshes_[kHead].Append(neck, T);
    meshes_[kHead].AddEllipsoid({0.01f, 0, 0.17f}, {0.1f, 0.085f, 0.12f}, 14, 10, m_skin, id, m_hair, 0.06f);
  }
  for (int s = 0; s < 2; ++s) {
    meshes_[kUpperArmL + s].AddLimb(float(kUpperArm), 0.05f, 0.042f, 8, m_shirt, id, 0.1f * float(s));
    meshes_[kForearmL + s].AddLimb(float(kForearm), 0.04f, 0.032f, 8, m_shirt, id, 0.05f);
    meshes_[kForearmL + s].AddEllipsoid({0.0f, 0, -0.31f}, {0.04f, 0.025f, 0.06f}, 8, 5, m_hand, id, m_hand, 1.f);
    meshes_[kThighL + s].AddLimb(float(kThigh), 0.075f, 0.056f, 8, m_pants, id, 0.2f * float(s));
    meshes_[kShinL + s].AddLimb(float(kShin), 0.052f, 0.042f, 8, m_pants, id, 0.3f);
    meshes_[kShinL + s].AddBox({-0.05f, -0.05f, -0.5f}, {0.2f, 0.05f, float(-kShin)}, m_shoes, id);
  }
}

std::array<SE3, kBodyPartCount> Humanoid::PartPoses(const BodyPose& p) const {
  std::array<SE3, kBodyPartCount> T;
  T[kPelvis] = Trans(p.root.x(), p.root.y(), p.root.z()) * Rz(p.yaw);
  T[kTorso] = T[kPelvis] * Trans(0, 0, kWaistZ) * Rz(p.torso_yaw) * Ry(p.torso_pitch);
  T[kHead] = T[kTorso] * Trans(0, 0, kNeckZ) * Rz(p.head_yaw) * Ry(p.head_pitch);
  for (int s = 0; s < 2; ++s) {
    const double side = s == 0 ? 1.0 : -1.0;  // left = +y
    T[kUpperArmL + s] = T[kTorso] * Trans(0, side * kShoulderY, kShoulderZ) * Rx(side * p.shoulder_out[s]) *
                        Ry(-p.shoulder_fwd[s]);
    T[kForearmL + s] = T[kUpperArmL + s] * Trans(0, 0, -kUpperArm) * Ry(-p.elbow[s]);
    T[kThighL + s] = T[kPelvis] * Trans(0, side * kHipY, kHipZ) * Ry(-p.hip[s]);
    T[kShinL + s] = T[kThighL + s] * Trans(0, 0, -kThigh) * Ry(p.knee[s]);
  }
  return T;
}

void Humanoid::Emit(const BodyPose& pose, int part_base, std::vector<DrawItem>* items) const {
  const auto T = PartPoses(pose);
  for (int i = 0; i < kBodyPartCount; ++i) {
    DrawItem d;
    d.mesh = &meshes_[size_t(i)];
    d.T_wo = T[size_t(i)];
    d.part = part_base + i;
    items->push_back(d);
  }
}

Vector3d Humanoid::HandPosition(const std::array<SE3, kBodyPartCount>& parts, int side) {
  return parts[size_t(kForearmL + side)] * Vector3d(0, 0, -0.31);
}

}  // namespace dynref::synth
