#include "synth/world.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/rng.h"

namespace dynref::synth {
namespace {

using Eigen::Vector3d;
constexpr double kPi = 3.14159265358979323846;
constexpr int kArcSamples = 720;
constexpr double kStride = 1.3;  // metres per full gait cycle

SE3 Pose2D(double x, double y, double z, double yaw) {
  SE3 T = SE3::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Vector3d(x, y, z);
  return T;
}

double Smooth(double u) {
  u = std::min(1.0, std::max(0.0, u));
  return u * u * (3 - 2 * u);
}
double Frac(double x) { return x - std::floor(x); }
double Bump(double u, double a, double b) {
  if (u < a || u > b) return 0;
  const double s = std::sin(kPi * (u - a) / (b - a));
  return s * s;
}
// 0 -> A -> A -> 0 -> 0 over one period: move, rest, move back, rest (bursts of motion).
double Burst(double t, double period, double amplitude) {
  const double u = Frac(t / period);
  if (u < 0.25) return amplitude * Smooth(u / 0.25);
  if (u < 0.5) return amplitude;
  if (u < 0.75) return amplitude * (1 - Smooth((u - 0.5) / 0.25));
  return 0;
}
// Pelvis height that keeps the lower foot on the floor (leg geometry of humanoid.cpp).
double LegHeight(double hip, double knee) {
  return 0.03 + 0.43 * std::cos(hip) + 0.5 * std::cos(hip - knee);
}
void Gait(double phase, double amplitude, BodyPose* p) {
  const double s = std::sin(phase), c = std::cos(phase);
  p->hip = {amplitude * s, -amplitude * s};
  p->knee = {0.08 + 1.5 * amplitude * std::pow(std::max(0.0, c), 1.5),
             0.08 + 1.5 * amplitude * std::pow(std::max(0.0, -c), 1.5)};
  p->shoulder_fwd = {-0.8 * amplitude * s, 0.8 * amplitude * s};
  p->elbow = {0.3 + 0.3 * amplitude * std::max(0.0, -s), 0.3 + 0.3 * amplitude * std::max(0.0, s)};
  p->root.z() = std::max(LegHeight(p->hip[0], p->knee[0]), LegHeight(p->hip[1], p->knee[1]));
}

Eigen::Matrix3d LookAt(const Vector3d& eye, const Vector3d& target) {
  const Vector3d z = (target - eye).normalized();
  const Vector3d x = z.cross(Vector3d::UnitZ()).normalized();
  const Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.col(0) = x, R.col(1) = y, R.col(2) = z;
  return R;  // world_from_camera (OpenCV axes)
}

void AppendWithInstance(Mesh* dst, const Mesh& src, const SE3& T, int instance) {
  Mesh copy = src;
  for (auto& t : copy.tris) t.instance = uint16_t(instance);
  dst->Append(copy, Eigen::Affine3f(T.matrix().cast<float>()));
}

ActorSpec Walker(double x, double y, double rx, double ry, double speed, double phase, double dir) {
  ActorSpec a;
  a.kind = ActorKind::kWalker, a.x = x, a.y = y, a.rx = rx, a.ry = ry, a.speed = speed, a.phase = phase, a.dir = dir;
  return a;
}
ActorSpec At(ActorKind kind, double x, double y, double yaw, double phase, bool moves_chair = false) {
  ActorSpec a;
  a.kind = kind, a.x = x, a.y = y, a.yaw = yaw, a.phase = phase, a.moves_chair = moves_chair;
  return a;
}

}  // namespace

std::vector<std::string> PresetNames() {
  return {"walking_xyz", "walking_static", "walking_halfsphere", "walking_rpy", "sitting_static", "sitting_xyz",
          "sitting_halfsphere", "sitting_rpy", "crowd", "person_tracking", "synchronous", "moving_box",
          "static_xyz", "static_rpy", "static_halfsphere", "static_lowtexture", "loop_static", "loop_walking"};
}

PresetSpec GetPreset(const std::string& name) {
  PresetSpec p;
  p.name = name;
  const auto has = [&](const char* prefix) { return name.rfind(prefix, 0) == 0; };
  const auto path_of = [&](const std::string& suffix) {
    if (suffix == "xyz") return CameraPath::kXyz;
    if (suffix == "rpy") return CameraPath::kRpy;
    if (suffix == "halfsphere") return CameraPath::kHalfsphere;
    if (suffix != "static") p.name = "";  // unknown camera motion
    return CameraPath::kStatic;
  };
  const ChairSpec left{-0.75, 0.75, kPi / 2}, right{0.75, 0.75, kPi / 2};
  if (has("walking_")) {
    // TUM fr3 walking_*: two people walk around in front of the desks; here one more pushes
    // the left chair back and forth (non-prior dynamic object, seed 002).
    p.camera = path_of(name.substr(8));
    p.actors = {Walker(0, -0.15, 2.1, 0.45, 1.0, 0.05, 1), Walker(0, -0.15, 1.3, 0.12, 0.8, 0.55, -1)};
    ActorSpec push = At(ActorKind::kPusher, -1.45, 0.72, 0, 3.0);
    push.speed = 0.9;
    p.actors.push_back(push);
    p.static_chairs = {right};
    p.default_frames = name == "walking_xyz" ? 859 : name == "walking_static" ? 743 : name == "walking_rpy" ? 910 : 1021;
  } else if (has("sitting_")) {
    // TUM fr3 sitting_*: two people sit at the desks, talk and gesture; one rolls its chair.
    p.camera = path_of(name.substr(8));
    p.actors = {At(ActorKind::kSitter, -0.55, 0.5, -kPi / 2 + 0.7, 0.0),
                At(ActorKind::kSitter, 0.6, 0.5, -kPi / 2 - 0.7, 2.5, true)};
    p.default_frames = name == "sitting_static" ? 707 : name == "sitting_xyz" ? 1261 : name == "sitting_rpy" ? 795 : 1110;
  } else if (name == "static_lowtexture") {
    // Issue 13's structure control: a plain room (few ORB corners, large planes, furniture
    // edges), the camera on the xyz path, nobody moving.
    p.camera = CameraPath::kXyz;
    p.plain_room = true;
    p.default_frames = 600;
  } else if (has("static_")) {
    p.camera = path_of(name.substr(7));
    p.static_chairs = {left, right};
    p.default_frames = 800;
    if (p.camera == CameraPath::kStatic) p.name = "";  // only xyz/rpy/halfsphere exist
  } else if (name == "loop_static" || name == "loop_walking") {
    // Issue 34's loop-closing sequence: the camera turns once around the room (loop path) and
    // looks at the desks again where it started; loop_walking adds the walking_* people.
    p.camera = CameraPath::kLoop;
    p.static_chairs = {left, right};
    if (name == "loop_walking")
      p.actors = {Walker(0, -0.15, 2.1, 0.45, 1.0, 0.05, 1), Walker(0, -0.15, 1.3, 0.12, 0.8, 0.55, -1)};
    p.default_frames = 720;
  } else if (name == "crowd") {
    // Bonn crowd: several people walking in lanes plus two standing and turning.
    p.camera = CameraPath::kHandheld;
    p.actors = {Walker(0, -0.65, 2.3, 0.1, 1.1, 0.1, 1), Walker(0, -0.2, 2.3, 0.1, 0.9, 0.6, -1),
                Walker(0, 0.25, 2.3, 0.1, 1.25, 0.35, 1), At(ActorKind::kTurner, 0.95, 0.75, -kPi / 2, 0),
                At(ActorKind::kTurner, -0.95, 0.75, -kPi / 2, 4.0)};
    p.default_frames = 895;
  } else if (name == "person_tracking") {
    // Bonn person_tracking: the camera follows one walking person.
    p.camera = CameraPath::kTracking;
    p.actors = {Walker(0, 0.0, 1.6, 0.3, 0.8, 0.0, 1)};
    p.static_chairs = {left, right};
    p.default_frames = 900;
  } else if (name == "synchronous") {
    // Bonn synchronous: several people jumping in sync.
    p.camera = CameraPath::kHandheld;
    p.actors = {At(ActorKind::kJumper, -0.8, 0.3, -kPi / 2, 0), At(ActorKind::kJumper, 0, 0.35, -kPi / 2, 0),
                At(ActorKind::kJumper, 0.8, 0.3, -kPi / 2, 0)};
    p.static_chairs = {left, right};
    p.default_frames = 900;
  } else if (name == "moving_box") {
    // Bonn moving_box: a person carries a box across the view.
    p.camera = CameraPath::kHandheld;
    ActorSpec c = Walker(0, 0.0, 1.7, 0.15, 0.5, 0.62, 1);
    c.kind = ActorKind::kCarrier;
    p.actors = {c};
    p.static_chairs = {left, right};
    p.default_frames = 900;
  } else {
    p.name = "";
  }
  if (p.name.empty()) {
    std::string list;
    for (const auto& n : PresetNames()) list += (list.empty() ? "" : ", ") + n;
    throw InputError("--preset", "unknown preset '" + name + "' (known: " + list + ")");
  }
  return p;
}

World::World(const PresetSpec& preset, uint64_t seed) : preset_(preset) {
  if (preset_.plain_room) BuildPlainRoom(seed, &scene_);
  else BuildOffice(seed, &scene_);
  if (preset_.camera == CameraPath::kLoop) AddLoopDecor(seed, &scene_);
  chair_mesh_ = BuildChairMesh(&scene_, seed, 0);
  box_mesh_ = BuildBoxMesh(&scene_, seed);
  int next_movable = kFirstMovableId;
  int static_chair_id = 190;
  for (const ChairSpec& c : preset_.static_chairs) {
    const int id = scene_.AddLabel(static_chair_id++, 56);
    AppendWithInstance(&scene_.static_mesh, chair_mesh_, Pose2D(c.x, c.y, 0, c.yaw), id);
  }
  Rng people(seed, "synth.people");
  int person_id = kFirstPersonId;
  for (const ActorSpec& spec : preset_.actors) {
    ActorRuntime a;
    a.spec = spec;
    a.body = std::make_unique<Humanoid>(scene_.AddLabel(person_id++, 0), people, &scene_.materials);
    if (spec.kind == ActorKind::kSitter || spec.kind == ActorKind::kPusher)
      a.chair_instance = scene_.AddLabel(next_movable++, 56);
    if (spec.kind == ActorKind::kCarrier) a.box_instance = scene_.AddLabel(next_movable++, -1, "box");
    if (spec.kind == ActorKind::kWalker || spec.kind == ActorKind::kCarrier) {
      a.arc.resize(kArcSamples + 1, 0.0);
      for (int k = 1; k <= kArcSamples; ++k) {
        const double t0 = 2 * kPi * (k - 1) / kArcSamples, t1 = 2 * kPi * k / kArcSamples;
        a.arc[size_t(k)] = a.arc[size_t(k - 1)] + std::hypot(spec.rx * (std::cos(t1) - std::cos(t0)),
                                                              spec.ry * (std::sin(t1) - std::sin(t0)));
      }
    }
    actors_.push_back(std::move(a));
  }
  Rng cam(seed, "synth.camera");
  for (double& ph : cam_phase_) ph = cam.Uniform(0, 2 * kPi);
  std::vector<DrawItem> items;
  Items(0.0, &items);
  item_body_part_.assign(items.size(), -1);
  for (const ActorRuntime& a : actors_)
    for (size_t i = 0; i < items.size(); ++i)
      if (items[i].mesh >= &a.body->part_mesh(0) && items[i].mesh <= &a.body->part_mesh(kBodyPartCount - 1))
        item_body_part_[i] = int(items[i].mesh - &a.body->part_mesh(0));
  for (const auto& it : items)
    item_instance_.push_back(it.instance_override > 0 ? it.instance_override
                                                      : (it.part == 0 ? 0 : int(it.mesh->tris[0].instance)));
}

Vector3d World::WalkerPoint(const ActorRuntime& a, double t, double* yaw, double* dist) const {
  const double perimeter = a.arc.back();
  *dist = a.spec.phase * perimeter + a.spec.speed * t;
  const double s = std::fmod(*dist, perimeter);
  const auto it = std::upper_bound(a.arc.begin(), a.arc.end(), s);
  const size_t k = size_t(std::max<long>(1, std::min<long>(kArcSamples, long(it - a.arc.begin()))));
  const double f = (s - a.arc[k - 1]) / std::max(1e-12, a.arc[k] - a.arc[k - 1]);
  const double th = a.spec.dir * 2 * kPi * (double(k - 1) + f) / kArcSamples;
  *yaw = std::atan2(a.spec.dir * a.spec.ry * std::cos(th), -a.spec.dir * a.spec.rx * std::sin(th));
  return {a.spec.x + a.spec.rx * std::cos(th), a.spec.y + a.spec.ry * std::sin(th), 0};
}

void World::ActorPose(const ActorRuntime& a, double t, BodyPose* p, SE3* obj) const {
  const ActorSpec& s = a.spec;
  *obj = SE3::Identity();
  *p = BodyPose();
  const double tp = t + s.phase;
  switch (s.kind) {
    case ActorKind::kWalker:
    case ActorKind::kCarrier: {
      double yaw = 0, dist = 0;
      const Vector3d q = WalkerPoint(a, t, &yaw, &dist);
      p->yaw = yaw;
      Gait(2 * kPi * dist / kStride, 0.42, p);
      p->root.x() = q.x(), p->root.y() = q.y();
      p->torso_pitch = 0.05;
      p->head_yaw = 0.25 * std::sin(2 * kPi * t / 4.3 + s.phase * 7);
      if (s.kind == ActorKind::kCarrier) {
        p->shoulder_fwd = {0.75, 0.75}, p->shoulder_out = {0.25, 0.25}, p->elbow = {0.85, 0.85};
        const auto parts = a.body->PartPoses(*p);
        *obj = parts[kTorso] * Pose2D(0.31, 0, 0.2, kPi / 2);
      }
      break;
    }
    case ActorKind::kPusher: {
      const double d = Burst(tp, 8.0, s.speed);
      const Vector3d dir(std::cos(s.yaw), std::sin(s.yaw), 0);
      p->yaw = s.yaw;
      Gait(2 * kPi * d / (s.speed / 2), 0.3, p);
      p->shoulder_fwd = {1.15, 1.15}, p->elbow = {0.45, 0.45}, p->shoulder_out = {0.12, 0.12};
      p->torso_pitch = 0.25;
      p->head_yaw = 0.35 * std::sin(2 * kPi * tp / 5.0);
      p->root.x() = s.x + d * dir.x(), p->root.y() = s.y + d * dir.y();
      *obj = Pose2D(p->root.x() + 0.66 * dir.x(), p->root.y() + 0.66 * dir.y(), 0, s.yaw);
      break;
    }
    case ActorKind::kSitter: {
      const double roll = s.moves_chair ? Burst(tp, 10.0, 0.3) : 0.0;
      const Vector3d fwd(std::cos(s.yaw), std::sin(s.yaw), 0);
      const double cx = s.x - roll * fwd.x(), cy = s.y - roll * fwd.y();
      *obj = Pose2D(cx, cy, 0, s.yaw);
      p->yaw = s.yaw;
      p->root = Vector3d(cx - 0.03 * fwd.x(), cy - 0.03 * fwd.y(), kSeatedRootZ);
      p->hip = {1.45, 1.45}, p->knee = {1.45, 1.45};
      const double act = Smooth(0.5 + 1.5 * std::sin(2 * kPi * tp / 7.0));
      p->shoulder_fwd = {0.6 + act * 0.45 * std::sin(2 * kPi * tp / 1.7), 0.5 + act * 0.4 * std::sin(2 * kPi * tp / 2.3 + 1)};
      p->elbow = {1.2 + act * 0.4 * std::sin(2 * kPi * tp / 1.3), 1.1 + act * 0.5 * std::sin(2 * kPi * tp / 1.9 + 2)};
      p->shoulder_out = {0.15 + 0.1 * act, 0.15};
      const double talk = Smooth(0.5 + 1.5 * std::sin(2 * kPi * tp / 5.3 + 1));
      p->head_yaw = 0.55 * talk * std::sin(2 * kPi * tp / 3.1);
      p->head_pitch = 0.12 * talk * std::sin(2 * kPi * tp / 2.2);
      p->torso_yaw = 0.2 * std::sin(2 * kPi * tp / 11.0);
      p->torso_pitch = 0.1;
      break;
    }
    case ActorKind::kTurner: {
      p->yaw = s.yaw + 1.3 * std::sin(2 * kPi * tp / 9.0);
      p->root = Vector3d(s.x, s.y, kStandingRootZ);
      p->shoulder_fwd = {0.2 + 0.3 * std::sin(2 * kPi * tp / 2.9), 0.1};
      p->elbow = {0.8 + 0.5 * std::sin(2 * kPi * tp / 2.1), 0.2};
      p->head_yaw = 0.4 * std::sin(2 * kPi * tp / 3.7);
      break;
    }
    case ActorKind::kJumper: {
      const double u = Frac(tp / 1.5);
      const double crouch = Bump(u, 0.0, 0.3) + Bump(u, 0.55, 0.8);
      const double flight = (u > 0.28 && u < 0.56) ? std::sin(kPi * (u - 0.28) / 0.28) : 0.0;
      p->yaw = s.yaw;
      p->hip = {0.6 * crouch, 0.6 * crouch}, p->knee = {1.1 * crouch, 1.1 * crouch};
      p->torso_pitch = 0.35 * crouch;
      p->shoulder_fwd = {-0.5 * crouch + 2.6 * flight, -0.5 * crouch + 2.6 * flight};
      p->shoulder_out = {0.1 + 0.3 * flight, 0.1 + 0.3 * flight};
      p->root = Vector3d(s.x, s.y, LegHeight(p->hip[0], p->knee[0]) + 0.28 * flight);
      break;
    }
  }
}

void World::Items(double t, std::vector<DrawItem>* items) const {
  items->clear();
  DrawItem room;
  room.mesh = &scene_.static_mesh;
  room.part = 0;
  items->push_back(room);
  for (const ActorRuntime& a : actors_) {
    BodyPose pose;
    SE3 obj;
    ActorPose(a, t, &pose, &obj);
    a.body->Emit(pose, int(items->size()), items);
    if (a.chair_instance > 0 || a.box_instance > 0) {
      DrawItem d;
      d.mesh = a.chair_instance > 0 ? &chair_mesh_ : &box_mesh_;
      d.T_wo = obj;
      d.instance_override = a.chair_instance > 0 ? a.chair_instance : a.box_instance;
      d.part = int(items->size());
      items->push_back(d);
    }
  }
}

SE3 World::CameraT_wc(double t) const {
  const double* ph = cam_phase_;
  const Vector3d eye0(0, -1.6, 1.35), target0(0, 1.4, 0.85);
  // Hand tremor: a few mm and a fraction of a degree at 1-4 Hz (handheld-smooth).
  const Vector3d tremor(0.002 * std::sin(2 * kPi * 1.3 * t + ph[0]) + 0.001 * std::sin(2 * kPi * 3.7 * t + ph[1]),
                        0.002 * std::sin(2 * kPi * 1.1 * t + ph[2]),
                        0.002 * std::sin(2 * kPi * 2.1 * t + ph[3]) + 0.001 * std::sin(2 * kPi * 3.1 * t + ph[4]));
  double yaw = 0.003 * std::sin(2 * kPi * 0.9 * t + ph[5]), pitch = 0.003 * std::sin(2 * kPi * 1.7 * t + ph[6]),
         roll = 0.002 * std::sin(2 * kPi * 1.3 * t + ph[7]);
  Vector3d eye = eye0 + tremor, target = target0;
  const auto wave = [&](double period, int i) { return std::sin(2 * kPi * t / period + ph[i]); };
  switch (preset_.camera) {
    case CameraPath::kStatic:
      break;
    case CameraPath::kXyz:  // slow translation along the three axes, +-0.4 m, fixed viewing direction
      eye += Vector3d(0.4 * wave(9.0, 0), 0.4 * wave(13.0, 1), 0.3 * wave(11.0, 2));
      target += eye - eye0 - tremor;
      yaw += 0.03 * wave(7.0, 3), pitch += 0.02 * wave(5.0, 4);
      break;
    case CameraPath::kRpy:  // rotation about the camera axes, +-25 degrees
      yaw += 0.44 * wave(7.0, 0), pitch += 0.3 * wave(9.0, 1), roll += 0.44 * wave(11.0, 2);
      break;
    case CameraPath::kHalfsphere: {  // on a half sphere (r = 0.5 m, ~1 m diameter) looking at the desks
      const double az = 1.1 * wave(14.0, 0), el = 0.4 + 0.35 * wave(9.0, 1);
      eye = Vector3d(0, -1.1, 1.2) + 0.5 * Vector3d(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el)) + tremor;
      break;
    }
    case CameraPath::kHandheld:
      eye += Vector3d(0.08 * wave(10.0, 0), 0.05 * wave(12.0, 1), 0.04 * wave(8.0, 2));
      yaw += 0.1 * wave(9.0, 3), pitch += 0.05 * wave(7.0, 4);
      break;
    case CameraPath::kLoop: {
      // One turn in kLoopPeriodS: the eye on a 0.35 m circle around (0, -1.3, 1.3), looking outwards
      // 20 deg down (desks, right wall, back wall, left wall, desks), then on over the start of the
      // turn again (72 deg in the last 4 s of 720 frames). It does not stop at the start view: a
      // still camera makes no keyframe (ORB-SLAM2's keyframe rule), and loop detection needs three
      // consecutive consistent keyframes in the revisited place (loop_static seed 2 stopped after
      // two, reports/loop_closing.md).
      const double kLoopPeriodS = 20.0;
      const double a = 2 * kPi * t / kLoopPeriodS;
      const Vector3d dir(std::sin(a), std::cos(a), 0);
      eye = Vector3d(0, -1.3, 1.3) + 0.35 * dir + tremor;
      target = eye + dir + Vector3d(0, 0, -0.36);
      break;
    }
    case CameraPath::kTracking: {  // follow actor 0 with a 0.3 s lag
      double wy = 0, dist = 0;
      const Vector3d q = WalkerPoint(actors_.front(), std::max(0.0, t - 0.3), &wy, &dist);
      eye += Vector3d(0.5 * q.x(), 0.3 * q.y(), 0);
      target = Vector3d(q.x(), q.y(), 1.05);
      break;
    }
  }
  const Eigen::Matrix3d R_look = LookAt(eye, target);
  const Eigen::Matrix3d R_pert = (Eigen::AngleAxisd(yaw, Vector3d::UnitY()) * Eigen::AngleAxisd(pitch, Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(roll, Vector3d::UnitZ())).toRotationMatrix();
  SE3 T_wc = SE3::Identity();
  T_wc.linear() = R_look * R_pert;
  T_wc.translation() = eye;
  return T_wc;
}

}  // namespace dynref::synth
