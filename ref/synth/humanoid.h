// Articulated humanoid: 11 rigid parts (pelvis, torso, head, upper/lower arms, thighs, shins with
// feet) driven by joint angles; textured clothing so that features land on people.
// Body frame: x forward, y left, z up; the root is the pelvis centre (hip height).
#pragma once
#include <array>
#include <vector>

#include "core/rng.h"
#include "synth/raster.h"
#include "synth/texture.h"

namespace dynref::synth {

struct BodyPose {
  Eigen::Vector3d root{0, 0, 0.96};   // world position of the pelvis centre
  double yaw = 0;                     // heading about world z (rad); 0 = facing world +x
  double torso_pitch = 0, torso_yaw = 0, head_yaw = 0, head_pitch = 0;
  // index 0 = left, 1 = right
  std::array<double, 2> shoulder_fwd{0, 0}, shoulder_out{0.08, 0.08}, elbow{0.1, 0.1};
  std::array<double, 2> hip{0, 0}, knee{0, 0};
};

enum BodyPart : int {
  kPelvis, kTorso, kHead, kUpperArmL, kUpperArmR, kForearmL, kForearmR, kThighL, kThighR,
  kShinL, kShinR, kBodyPartCount
};

constexpr double kStandingRootZ = 0.96;  // pelvis height of a straight-legged person
constexpr double kSeatedRootZ = 0.54;    // on a chair seat of height 0.5 m

class Humanoid {
 public:
  // Builds meshes with clothing/skin materials appended to `materials`; `instance` is the
  // scene-wide id painted into every triangle. Appearance drawn from rng.
  Humanoid(int instance, Rng& rng, std::vector<Material>* materials);
  int instance() const { return instance_; }
  // World poses of every part for a body pose.
  std::array<SE3, kBodyPartCount> PartPoses(const BodyPose& pose) const;
  // Appends one DrawItem per part, parts numbered part_base + BodyPart.
  void Emit(const BodyPose& pose, int part_base, std::vector<DrawItem>* items) const;
  // World position of a hand (for carrying/pushing).
  static Eigen::Vector3d HandPosition(const std::array<SE3, kBodyPartCount>& parts, int side);
  const Mesh& part_mesh(int part) const { return meshes_[size_t(part)]; }

 private:
  int instance_;
  std::array<Mesh, kBodyPartCount> meshes_;
};

}  // namespace dynref::synth
