// The static office resembling TUM fr3 "office" scenes: two desks with monitors, keyboards,
// books, cubicle partitions, posters, whiteboard, shelves, floor, ceiling with lights and beams.
// World frame: z up, metres; the camera looks roughly along +y at the desks.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "synth/raster.h"
#include "synth/texture.h"

namespace dynref::synth {

struct Light {
  Eigen::Vector3f pos_w;
  float intensity = 1.f;
};

struct InstanceLabel {
  std::string class_name;   // one token; COCO name when coco_id >= 0
  int coco_id = -1;
  bool prior_dynamic = false;
};

// Instance id ranges (stable, scene-wide): people 1..19, movable objects 20..49, static >= 100.
constexpr int kFirstPersonId = 1;
constexpr int kFirstMovableId = 20;
constexpr int kFirstStaticId = 100;

struct Scene {
  std::vector<Material> materials;
  std::vector<Light> lights;
  std::map<int, InstanceLabel> labels;   // every instance id that can appear in a frame
  Mesh static_mesh;                      // room, furniture, static objects (world frame)
  int AddMaterial(const Material& m);
  int AddLabel(int id, int coco_id, const std::string& name_if_not_coco = "");
};

// Builds the room and furniture (no chairs: presets place them). Textures seeded from
// Rng(seed, "synth.scene").
void BuildOffice(uint64_t seed, Scene* scene);
// A low-texture room (issue 13's structure control): the same shell size with plain, evenly lit
// walls in two colours, a plain floor and ceiling, and furniture of plain boxes (a table, a
// cabinet, a bookcase frame, two crates) whose edges and faces give lines and planes while ORB
// corners are scarce. Textures seeded from Rng(seed, "synth.scene").
void BuildPlainRoom(uint64_t seed, Scene* scene);
// Posters on the walls the office leaves bare, for the loop presets (issue 34).
void AddLoopDecor(uint64_t seed, Scene* scene);
// Office chair in its own frame: origin on the floor under the seat centre, seat faces +x.
Mesh BuildChairMesh(Scene* scene, uint64_t seed, int variant);
// Cardboard box (0.44 x 0.34 x 0.30 m) centred at the origin.
Mesh BuildBoxMesh(Scene* scene, uint64_t seed);

}  // namespace dynref::synth
