// Presets (scene content, actors, camera path) and the time-continuous world: every pose is a
// smooth function of time t (seconds since the first frame), so motion blur can integrate
// sub-frame renders and motion flags compare t with t - 1/30 s.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "synth/humanoid.h"
#include "synth/raster.h"
#include "synth/scene.h"

namespace dynref::synth {

enum class CameraPath { kXyz, kRpy, kHalfsphere, kStatic, kHandheld, kTracking, kLoop };
enum class ActorKind { kWalker, kPusher, kSitter, kTurner, kCarrier, kJumper };

struct ActorSpec {
  ActorKind kind = ActorKind::kWalker;
  double x = 0, y = 0;        // walker/carrier: ellipse centre; others: position
  double rx = 1, ry = 0.2;    // walker/carrier ellipse radii (m)
  double speed = 1.0;         // m/s along the path; pusher: push distance (m)
  double phase = 0;           // walker: start fraction of the loop; others: time offset (s)
  double dir = 1;             // walker: +1 counter-clockwise, -1 clockwise
  double yaw = 0;             // sitter/turner/jumper/pusher heading (rad)
  bool moves_chair = false;   // sitter rolls its chair in bursts; pusher always has a chair
};

struct ChairSpec {
  double x = 0, y = 0, yaw = 0;
};

struct PresetSpec {
  std::string name;
  int default_frames = 900;
  CameraPath camera = CameraPath::kStatic;
  std::vector<ActorSpec> actors;
  std::vector<ChairSpec> static_chairs;
  bool plain_room = false;  // BuildPlainRoom instead of BuildOffice (static_lowtexture)
};

std::vector<std::string> PresetNames();
PresetSpec GetPreset(const std::string& name);  // InputError listing the names if unknown

class World {
 public:
  World(const PresetSpec& preset, uint64_t seed);
  const Scene& scene() const { return scene_; }
  const PresetSpec& preset() const { return preset_; }
  // Draw items at time t; item order and count never change, items[i].part == i.
  void Items(double t, std::vector<DrawItem>* items) const;
  SE3 CameraT_wc(double t) const;
  // Instance id of item i (0 for the static room: it never moves).
  int ItemInstance(size_t i) const { return item_instance_[i]; }
  size_t ItemCount() const { return item_instance_.size(); }
  // BodyPart of item i for people (limbs for "missing limb" degradation), -1 otherwise.
  int ItemBodyPart(size_t i) const { return item_body_part_[i]; }

 private:
  struct ActorRuntime {
    ActorSpec spec;
    std::unique_ptr<Humanoid> body;
    int chair_instance = 0;   // pusher / rolling sitter
    int box_instance = 0;     // carrier
    std::vector<double> arc;  // walker: cumulative arc length at kArcSamples angles
  };
  void ActorPose(const ActorRuntime& a, double t, BodyPose* pose, SE3* object_T_wo) const;
  Eigen::Vector3d WalkerPoint(const ActorRuntime& a, double t, double* yaw, double* dist) const;

  PresetSpec preset_;
  Scene scene_;
  Mesh chair_mesh_, box_mesh_;
  std::vector<ActorRuntime> actors_;
  std::vector<int> item_instance_;
  std::vector<int> item_body_part_;
  double cam_phase_[8] = {0};
};

}  // namespace dynref::synth
