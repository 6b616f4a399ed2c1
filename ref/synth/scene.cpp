#include "synth/scene.h"

#include <cmath>

#include "core/rng.h"
#include "io/coco_classes.h"

namespace dynref::synth {
namespace {

using Eigen::Vector3f;
using V = Vector3f;

Rgb C(float r, float g, float b) { return {r, g, b}; }

Material Mat(Pattern p, Rgb c0, Rgb c1, Rgb c2, float scale, Rng& rng, float emission = 0.f) {
  Material m;
  m.pattern = p, m.c0 = c0, m.c1 = c1, m.c2 = c2, m.scale = scale, m.emission = emission;
  m.seed = uint32_t(rng.NextU64());
  return m;
}

// Quad in the plane y = y0 spanning x0..x1, z0..z1 (posters on walls facing +-y).
void QuadY(Mesh* m, float y0, float x0, float x1, float z0, float z1, int mat, int inst) {
  m->AddQuad(V(x0, y0, z0), V(x1, y0, z0), V(x1, y0, z1), V(x0, y0, z1), mat, inst, {x0, z0});
}
void QuadX(Mesh* m, float x0, float y0, float y1, float z0, float z1, int mat, int inst) {
  m->AddQuad(V(x0, y0, z0), V(x0, y1, z0), V(x0, y1, z1), V(x0, y0, z1), mat, inst, {y0, z0});
}
void QuadZ(Mesh* m, float z0, float x0, float x1, float y0, float y1, int mat, int inst) {
  m->AddQuad(V(x0, y0, z0), V(x1, y0, z0), V(x1, y1, z0), V(x0, y1, z0), mat, inst, {x0, y0});
}

// Floor, ceiling, the two walls facing +-y, then the two facing +-x (this order: the mesh, and
// so every rendered byte, depends on it).
void RoomShell(Mesh* m, float X0, float X1, float Y0, float Y1, float H, int floor, int ceiling, int wall, int wall2) {
  QuadZ(m, 0, X0, X1, Y0, Y1, floor, 0);
  QuadZ(m, H, X0, X1, Y0, Y1, ceiling, 0);
  QuadY(m, Y1, X0, X1, 0, H, wall, 0);
  QuadY(m, Y0, X0, X1, 0, H, wall, 0);
  QuadX(m, X0, Y0, Y1, 0, H, wall2, 0);
  QuadX(m, X1, Y0, Y1, 0, H, wall2, 0);
}

}  // namespace

int Scene::AddMaterial(const Material& m) {
  materials.push_back(m);
  return int(materials.size()) - 1;
}

int Scene::AddLabel(int id, int coco_id, const std::string& name_if_not_coco) {
  InstanceLabel l;
  l.coco_id = coco_id;
  l.class_name = coco_id >= 0 ? CocoClassName(coco_id) : name_if_not_coco;
  l.prior_dynamic = coco_id >= 0 && CocoIsPriorDynamic(coco_id);
  labels[id] = l;
  return id;
}

void BuildPlainRoom(uint64_t seed, Scene* s) {
  Rng rng(seed, "synth.scene");
  Mesh& m = s->static_mesh;
  const Rgb white = C(0.85f, 0.85f, 0.82f), dark = C(0.06f, 0.06f, 0.07f);
  const int floor = s->AddMaterial(Mat(Pattern::kFlat, C(0.45f, 0.42f, 0.38f), white, dark, 1, rng));
  const int ceiling = s->AddMaterial(Mat(Pattern::kFlat, C(0.82f, 0.82f, 0.80f), white, dark, 1, rng));
  const int light = s->AddMaterial(Mat(Pattern::kLight, C(1, 1, 0.97f), C(0.6f, 0.6f, 0.6f), dark, 0.3f, rng, 3.0f));
  const int wall = s->AddMaterial(Mat(Pattern::kFlat, C(0.78f, 0.76f, 0.70f), white, dark, 1, rng));
  const int wall2 = s->AddMaterial(Mat(Pattern::kFlat, C(0.60f, 0.68f, 0.74f), white, dark, 1, rng));
  const int top = s->AddMaterial(Mat(Pattern::kFlat, C(0.30f, 0.22f, 0.16f), white, dark, 1, rng));
  const int metal = s->AddMaterial(Mat(Pattern::kFlat, C(0.20f, 0.20f, 0.22f), white, dark, 1, rng));
  const int cabinet = s->AddMaterial(Mat(Pattern::kFlat, C(0.92f, 0.92f, 0.90f), white, dark, 1, rng));
  const int crate = s->AddMaterial(Mat(Pattern::kFlat, C(0.70f, 0.30f, 0.20f), white, dark, 1, rng));
  const int crate2 = s->AddMaterial(Mat(Pattern::kFlat, C(0.25f, 0.45f, 0.30f), white, dark, 1, rng));
  const float X0 = -2.8f, X1 = 2.8f, Y0 = -2.6f, Y1 = 2.45f, H = 2.7f;
  RoomShell(&m, X0, X1, Y0, Y1, H, floor, ceiling, wall, wall2);
  m.AddBox(V(X0, Y1 - 0.02f, 0), V(X1, Y1, 0.1f), metal, 0);  // skirting: a long floor edge
  for (float x : {-1.5f, 0.f, 1.5f}) {
    QuadZ(&m, H - 0.01f, x - 0.3f, x + 0.3f, 0.2f - 0.6f, 0.2f + 0.6f, light, 0);
    s->lights.push_back({V(x, 0.2f, H - 0.25f), 1.0f});
  }
  // Table: top and four legs.
  m.AddBox(V(-0.8f, 0.9f, 0.72f), V(0.8f, 1.7f, 0.76f), top, kFirstStaticId);
  for (float x : {-0.76f, 0.72f})
    for (float y : {0.94f, 1.62f}) m.AddBox(V(x, y, 0), V(x + 0.04f, y + 0.04f, 0.72f), metal, kFirstStaticId);
  // Cabinet against the back wall (left), bookcase frame (right), two crates on the floor.
  m.AddBox(V(-2.4f, 1.95f, 0), V(-1.5f, Y1 - 0.02f, 1.1f), cabinet, kFirstStaticId + 1);
  m.AddBox(V(1.5f, 2.05f, 0), V(1.55f, Y1 - 0.02f, 1.9f), metal, kFirstStaticId + 2);
  m.AddBox(V(2.35f, 2.05f, 0), V(2.4f, Y1 - 0.02f, 1.9f), metal, kFirstStaticId + 2);
  for (float z : {0.0f, 0.6f, 1.2f, 1.85f}) m.AddBox(V(1.5f, 2.05f, z), V(2.4f, Y1 - 0.02f, z + 0.05f), metal, kFirstStaticId + 2);
  m.AddBox(V(-1.2f, 0.2f, 0), V(-0.7f, 0.6f, 0.4f), crate, kFirstStaticId + 3);
  m.AddBox(V(1.0f, 0.4f, 0), V(1.45f, 0.8f, 0.5f), crate2, kFirstStaticId + 4);
  s->AddLabel(kFirstStaticId, 60);  // COCO dining table
  s->AddLabel(kFirstStaticId + 1, -1, "cabinet");
  s->AddLabel(kFirstStaticId + 2, -1, "shelf");
  s->AddLabel(kFirstStaticId + 3, -1, "crate");
  s->AddLabel(kFirstStaticId + 4, -1, "crate");
}

namespace {

// The office's shared materials, drawn from the scene RNG in declaration order.
struct OfficeMaterials {
  int carpet, ceiling, light, wall, wall2, beam, fabric, frame, wood, plastic, grey, board, keys, spines, binders, plant;
};

// State shared by the office building steps: scene, static mesh, scene RNG, next instance id.
// Room shell: x in [-2.8, 2.8], y in [-2.6, 2.45], z in [0, 2.7].
struct OfficeBuilder {
  Scene* s;
  Mesh& m;
  Rng& rng;
  Rgb white, dark;
  OfficeMaterials mat;
  int id;
  float X0 = -2.8f, X1 = 2.8f, Y0 = -2.6f, Y1 = 2.45f, H = 2.7f;
};

OfficeMaterials OfficeAddMaterials(Scene* s, Rng& rng, const Rgb& white, const Rgb& dark) {
  OfficeMaterials k;
  k.carpet = s->AddMaterial(Mat(Pattern::kCarpet, C(0.32f, 0.32f, 0.36f), C(0.42f, 0.38f, 0.34f), dark, 0.5f, rng));
  k.ceiling = s->AddMaterial(Mat(Pattern::kCeiling, C(0.8f, 0.8f, 0.78f), C(0.55f, 0.55f, 0.55f), dark, 0.6f, rng));
  k.light = s->AddMaterial(Mat(Pattern::kLight, C(1, 1, 0.97f), C(0.6f, 0.6f, 0.6f), dark, 0.3f, rng, 3.0f));
  k.wall = s->AddMaterial(Mat(Pattern::kPaint, C(0.78f, 0.75f, 0.68f), white, dark, 1, rng));
  k.wall2 = s->AddMaterial(Mat(Pattern::kPaint, C(0.62f, 0.70f, 0.74f), white, dark, 1, rng));
  k.beam = s->AddMaterial(Mat(Pattern::kMetal, C(0.65f, 0.65f, 0.66f), white, dark, 1, rng));
  k.fabric = s->AddMaterial(Mat(Pattern::kFabric, C(0.30f, 0.36f, 0.45f), white, dark, 1, rng));
  k.frame = s->AddMaterial(Mat(Pattern::kMetal, C(0.5f, 0.5f, 0.52f), white, dark, 1, rng));
  k.wood = s->AddMaterial(Mat(Pattern::kWood, C(0.62f, 0.45f, 0.28f), C(0.42f, 0.28f, 0.16f), dark, 1, rng));
  k.plastic = s->AddMaterial(Mat(Pattern::kFlat, C(0.08f, 0.08f, 0.09f), white, dark, 1, rng));
  k.grey = s->AddMaterial(Mat(Pattern::kFlat, C(0.55f, 0.56f, 0.58f), white, dark, 1, rng));
  k.board = s->AddMaterial(Mat(Pattern::kWhiteboard, C(0.93f, 0.93f, 0.92f), C(0.1f, 0.15f, 0.6f), C(0.7f, 0.1f, 0.1f), 1, rng));
  k.keys = s->AddMaterial(Mat(Pattern::kKeyboard, C(0.2f, 0.2f, 0.22f), C(0.03f, 0.03f, 0.03f), C(0.85f, 0.85f, 0.85f), 1, rng));
  k.spines = s->AddMaterial(Mat(Pattern::kSpines, C(0.12f, 0.1f, 0.08f), C(0.9f, 0.88f, 0.8f), C(0.8f, 0.7f, 0.1f), 0.035f, rng));
  k.binders = s->AddMaterial(Mat(Pattern::kSpines, C(0.1f, 0.1f, 0.1f), white, dark, 0.07f, rng));
  k.plant = s->AddMaterial(Mat(Pattern::kPrint, C(0.12f, 0.35f, 0.12f), C(0.05f, 0.2f, 0.05f), C(0.3f, 0.55f, 0.2f), 0.05f, rng));
  return k;
}

// Room shell, skirting boards, ceiling lights and beams.
void OfficeShell(OfficeBuilder& b) {
  Mesh& m = b.m;
  const OfficeMaterials& k = b.mat;
  const float X0 = b.X0, X1 = b.X1, Y0 = b.Y0, Y1 = b.Y1, H = b.H;
  RoomShell(&m, X0, X1, Y0, Y1, H, k.carpet, k.ceiling, k.wall, k.wall2);
  // Skirting boards give long straight edges at the floor.
  m.AddBox(V(X0, Y1 - 0.02f, 0), V(X1, Y1, 0.1f), k.plastic, 0);
  m.AddBox(V(X0, Y0, 0), V(X0 + 0.02f, Y1, 0.1f), k.plastic, 0);
  m.AddBox(V(X1 - 0.02f, Y0, 0), V(X1, Y1, 0.1f), k.plastic, 0);
  // Ceiling lights and beams.
  const float lx[3] = {-1.5f, 0.f, 1.5f}, ly[3] = {-1.4f, 0.2f, 1.7f};
  for (float x : lx)
    for (float y : ly) {
      QuadZ(&m, H - 0.01f, x - 0.3f, x + 0.3f, y - 0.6f, y + 0.6f, k.light, 0);
      b.s->lights.push_back({V(x, y, H - 0.25f), 1.0f});
    }
  for (float y : {-0.5f, 1.2f}) m.AddBox(V(X0, y - 0.08f, H - 0.22f), V(X1, y + 0.08f, H), k.beam, 0);
  m.AddBox(V(-0.08f, Y0, H - 0.18f), V(0.08f, Y1, H), k.beam, 0);
}

// Back wall: whiteboard, posters, clock.
void OfficeBackWall(OfficeBuilder& b) {
  Mesh& m = b.m;
  Scene* s = b.s;
  Rng& rng = b.rng;
  const Rgb white = b.white, dark = b.dark;
  const float Y1 = b.Y1;
  m.AddBox(V(-1.0f, Y1 - 0.03f, 0.95f), V(1.0f, Y1, 2.05f), b.mat.frame, 0);
  QuadY(&m, Y1 - 0.035f, -0.97f, 0.97f, 0.98f, 2.02f, b.mat.board, 0);
  for (int i = 0; i < 3; ++i) {
    const float x = -2.55f + 0.55f * float(i);
    const int poster = s->AddMaterial(Mat(Pattern::kPrint, C(0.9f, 0.88f, 0.8f), dark, C(0.7f, 0.2f, 0.1f),
                                          float(rng.Uniform(0.07, 0.14)), rng));
    QuadY(&m, Y1 - 0.01f, x, x + 0.45f, 1.2f + 0.1f * float(i % 2), 1.85f + 0.1f * float(i % 2), poster, 0);
  }
  Mesh clock;
  const int face = s->AddMaterial(Mat(Pattern::kPrint, white, dark, C(0.8f, 0.1f, 0.1f), 0.06f, rng));
  clock.AddLimb(0.04f, 0.16f, 0.16f, 16, face, s->AddLabel(b.id++, 74));
  Eigen::Affine3f T = Eigen::Affine3f::Identity();
  T.translate(V(1.3f, Y1, 2.25f));
  T.rotate(Eigen::AngleAxisf(-1.5707963f, V::UnitX()));
  m.Append(clock, T);
}

// Shelf (frame + boards + rows of books) right, cabinet left, potted plant next to the cabinet.
void OfficeShelvesAndPlant(OfficeBuilder& b) {
  Mesh& m = b.m;
  Scene* s = b.s;
  Rng& rng = b.rng;
  const OfficeMaterials& k = b.mat;
  const Rgb white = b.white, dark = b.dark;
  const float Y1 = b.Y1;
  const float sx0 = 1.25f, sx1 = 2.55f, sy0 = Y1 - 0.38f;
  m.AddBox(V(sx0, sy0, 0), V(sx0 + 0.03f, Y1, 2.0f), k.wood, 0);
  m.AddBox(V(sx1 - 0.03f, sy0, 0), V(sx1, Y1, 2.0f), k.wood, 0);
  for (int i = 0; i < 5; ++i) {
    const float z = 0.05f + 0.48f * float(i);
    m.AddBox(V(sx0, sy0, z), V(sx1, Y1, z + 0.025f), k.wood, 0);
    if (i < 4) {
      const int row = s->AddMaterial(Mat(Pattern::kSpines, C(0.12f, 0.1f, 0.08f), C(0.9f, 0.88f, 0.8f), C(0.8f, 0.7f, 0.1f),
                                         float(rng.Uniform(0.03, 0.05)), rng));
      m.AddBoxFront(V(sx0 + 0.04f, sy0 + 0.05f, z + 0.025f), V(sx1 - 0.04f, Y1 - 0.02f, z + 0.025f + 0.26f), k.plastic,
                    row, 0, -1);
    }
  }
  m.AddBoxFront(V(-2.6f, Y1 - 0.45f, 0), V(-1.7f, Y1, 1.15f), k.grey, k.binders, 0, -1);
  m.AddBox(V(-2.6f, Y1 - 0.45f, 1.15f), V(-1.7f, Y1, 1.18f), k.wood, 0);
  m.AddBoxFront(V(-2.5f, Y1 - 0.3f, 1.18f), V(-1.9f, Y1 - 0.05f, 1.45f), k.plastic, k.spines, 0, -1);
  Mesh p;
  const int pot = s->AddMaterial(Mat(Pattern::kFlat, C(0.6f, 0.3f, 0.15f), white, dark, 1, rng));
  const int pid = s->AddLabel(b.id++, 58);
  p.AddLimb(0.35f, 0.16f, 0.12f, 12, pot, pid);
  p.AddEllipsoid(V(0, 0, 0.35f), V(0.3f, 0.3f, 0.4f), 12, 8, k.plant, pid, k.plant, 1.f);
  Eigen::Affine3f T = Eigen::Affine3f::Identity();
  T.translate(V(-2.3f, 1.6f, 0.35f));
  m.Append(p, T);
}

// Door and posters on the side walls; cubicle partitions (back panel at y = 1.85..1.9, side
// panels at x = +-1.6) with papers pinned.
void OfficeSideWallsAndPartitions(OfficeBuilder& b) {
  Mesh& m = b.m;
  Scene* s = b.s;
  Rng& rng = b.rng;
  const OfficeMaterials& k = b.mat;
  const Rgb white = b.white, dark = b.dark;
  const float X0 = b.X0, X1 = b.X1;
  m.AddBox(V(X1 - 0.05f, -1.6f, 0), V(X1, -0.7f, 2.1f), k.wood, 0);
  for (int i = 0; i < 2; ++i) {
    const int poster = s->AddMaterial(Mat(Pattern::kPrint, C(0.15f, 0.2f, 0.3f), white, C(0.9f, 0.7f, 0.2f),
                                          float(rng.Uniform(0.08, 0.15)), rng));
    QuadX(&m, X0 + 0.01f, -0.4f + 1.3f * float(i), 0.4f + 1.3f * float(i), 1.1f, 1.9f, poster, 0);
    QuadX(&m, X1 - 0.01f, 0.2f + 1.1f * float(i), 0.9f + 1.1f * float(i), 1.2f, 1.8f, poster, 0);
  }
  const float py0 = 1.85f, py1 = 1.9f, ph = 1.35f;
  m.AddBox(V(-2.0f, py0, 0), V(2.0f, py1, ph), k.fabric, 0);
  m.AddBox(V(-2.0f, py0 - 0.01f, ph), V(2.0f, py1 + 0.01f, ph + 0.03f), k.frame, 0);
  for (float x : {-1.65f, 1.6f}) {
    m.AddBox(V(x, 0.9f, 0), V(x + 0.05f, py0, ph), k.fabric, 0);
    m.AddBox(V(x - 0.01f, 0.9f, ph), V(x + 0.06f, py0, ph + 0.03f), k.frame, 0);
  }
  for (int i = 0; i < 9; ++i) {
    const float x = -1.55f + 0.36f * float(i) + float(rng.Uniform(-0.05, 0.05));
    const float z = float(rng.Uniform(0.85, 1.05));
    const int paper = s->AddMaterial(Mat(Pattern::kPrint, C(0.92f, 0.92f, 0.9f), dark, C(0.2f, 0.3f, 0.7f),
                                         float(rng.Uniform(0.04, 0.07)), rng));
    QuadY(&m, py0 - 0.005f, x, x + 0.21f, z, z + 0.28f, paper, 0);
  }
}

// Desk d's desk body and its monitors, keyboards and mice.
void OfficeDeskAndMonitors(OfficeBuilder& b, int d, float x0, float x1, float xc) {
  Mesh& m = b.m;
  Scene* s = b.s;
  Rng& rng = b.rng;
  const OfficeMaterials& k = b.mat;
  const int desk = s->AddLabel(b.id++, 60);
  m.AddBox(V(x0, 1.0f, 0.70f), V(x1, 1.8f, 0.74f), k.wood, desk);
  m.AddBox(V(x0 + 0.02f, 1.05f, 0), V(x0 + 0.05f, 1.78f, 0.70f), k.grey, desk);
  m.AddBox(V(x1 - 0.05f, 1.05f, 0), V(x1 - 0.02f, 1.78f, 0.70f), k.grey, desk);
  m.AddBox(V(x0 + 0.05f, 1.7f, 0.25f), V(x1 - 0.05f, 1.73f, 0.70f), k.grey, desk);
  for (int i = 0; i < (d == 0 ? 1 : 2); ++i) {
    const float mx = d == 0 ? xc + 0.2f : xc - 0.33f + 0.66f * float(i);
    const int mon = s->AddLabel(b.id++, 62);
    const int screen = s->AddMaterial(Mat(Pattern::kPrint, C(0.12f, 0.14f, 0.2f), C(0.85f, 0.85f, 0.85f),
                                          C(0.3f, 0.6f, 0.9f), float(rng.Uniform(0.05, 0.09)), rng, 0.6f));
    m.AddBox(V(mx - 0.12f, 1.45f, 0.74f), V(mx + 0.12f, 1.62f, 0.76f), k.plastic, mon);
    m.AddBox(V(mx - 0.03f, 1.55f, 0.76f), V(mx + 0.03f, 1.58f, 0.95f), k.plastic, mon);
    m.AddBoxFront(V(mx - 0.3f, 1.5f, 0.88f), V(mx + 0.3f, 1.55f, 1.24f), k.plastic, k.plastic, mon, -1);
    QuadY(&m, 1.499f, mx - 0.28f, mx + 0.28f, 0.9f, 1.22f, screen, mon);
    const int kb = s->AddLabel(b.id++, 66);
    m.AddBox(V(mx - 0.22f, 1.12f, 0.74f), V(mx + 0.22f, 1.28f, 0.76f), k.plastic, kb);
    QuadZ(&m, 0.7605f, mx - 0.215f, mx + 0.215f, 1.125f, 1.275f, k.keys, kb);
    const int mouse = s->AddLabel(b.id++, 64);
    m.AddBox(V(mx + 0.3f, 1.15f, 0.74f), V(mx + 0.36f, 1.25f, 0.77f), k.grey, mouse);
  }
}

// Desk d's books (a stack and a few upright ones), cup and paper.
void OfficeDeskItems(OfficeBuilder& b, int d, float x0, float x1, float xc) {
  Mesh& m = b.m;
  Scene* s = b.s;
  Rng& rng = b.rng;
  const Rgb white = b.white, dark = b.dark;
  float z = 0.74f;
  for (int i = 0; i < 4; ++i) {
    const int book = s->AddLabel(b.id++, 73);
    const float w = float(rng.Uniform(0.17, 0.25)), dd = float(rng.Uniform(0.22, 0.3)), t = float(rng.Uniform(0.025, 0.05));
    const int cover = s->AddMaterial(Mat(Pattern::kPrint, C(float(rng.Uniform(0.1, 0.9)), float(rng.Uniform(0.1, 0.9)),
                                                             float(rng.Uniform(0.1, 0.9))), dark, white,
                                         float(rng.Uniform(0.04, 0.08)), rng));
    const float bx = (d == 0 ? x0 + 0.15f : x1 - 0.4f) + float(rng.Uniform(-0.03, 0.03));
    m.AddBoxFront(V(bx, 1.3f, z), V(bx + w, 1.3f + dd, z + t), cover, cover, book, -1);
    QuadZ(&m, z + t + 0.0005f, bx, bx + w, 1.3f, 1.3f + dd, cover, book);
    z += t;
  }
  for (int i = 0; i < 5; ++i) {
    const int book = s->AddLabel(b.id++, 73);
    const int cover = s->AddMaterial(Mat(Pattern::kSpines, C(float(rng.Uniform(0.1, 0.8)), 0.2f, 0.3f), white, C(0.9f, 0.8f, 0.1f),
                                         0.05f, rng));
    const float bx = (d == 0 ? x1 - 0.45f : x0 + 0.12f) + 0.045f * float(i);
    const float hb = float(rng.Uniform(0.2, 0.28));
    m.AddBoxFront(V(bx, 1.62f, 0.74f), V(bx + 0.04f, 1.8f, 0.74f + hb), cover, cover, book, -1);
  }
  const int cup = s->AddLabel(b.id++, 41);
  const int mug = s->AddMaterial(Mat(Pattern::kPrint, white, C(0.7f, 0.1f, 0.1f), dark, 0.03f, rng));
  Mesh c;
  c.AddLimb(0.1f, 0.04f, 0.037f, 12, mug, cup);
  Eigen::Affine3f T = Eigen::Affine3f::Identity();
  T.translate(V(d == 0 ? xc - 0.35f : xc + 0.05f, 1.1f, 0.84f));
  m.Append(c, T);
  const int paper = s->AddMaterial(Mat(Pattern::kPrint, C(0.93f, 0.93f, 0.9f), dark, C(0.6f, 0.1f, 0.1f), 0.05f, rng));
  QuadZ(&m, 0.7405f, xc - 0.1f, xc + 0.11f, 1.02f, 1.1f + 0.2f * float(d), paper, 0);
}

// The laptop on the left desk.
void OfficeLaptop(OfficeBuilder& b) {
  Scene* s = b.s;
  const int lap = s->AddLabel(b.id++, 63);
  const int lscreen = s->AddMaterial(Mat(Pattern::kPrint, C(0.9f, 0.9f, 0.92f), C(0.1f, 0.1f, 0.2f), C(0.9f, 0.4f, 0.1f),
                                         0.05f, b.rng, 0.5f));
  Mesh l;
  l.AddBox(V(-0.17f, -0.12f, 0), V(0.17f, 0.12f, 0.02f), b.mat.grey, lap);
  QuadZ(&l, 0.0205f, -0.15f, 0.15f, -0.1f, 0.05f, b.mat.keys, lap);
  Mesh scr;
  scr.AddBox(V(-0.17f, 0, 0), V(0.17f, 0.01f, 0.23f), b.mat.grey, lap);
  QuadY(&scr, -0.001f, -0.155f, 0.155f, 0.015f, 0.215f, lscreen, lap);
  Eigen::Affine3f Ts = Eigen::Affine3f::Identity();
  Ts.translate(V(0, 0.12f, 0.02f));
  Ts.rotate(Eigen::AngleAxisf(-0.3f, V::UnitX()));
  l.Append(scr, Ts);
  Eigen::Affine3f T = Eigen::Affine3f::Identity();
  T.translate(V(-1.2f, 1.3f, 0.74f));
  T.rotate(Eigen::AngleAxisf(0.25f, V::UnitZ()));
  b.m.Append(l, T);
}

}  // namespace

void BuildOffice(uint64_t seed, Scene* s) {
  Rng rng(seed, "synth.scene");
  const Rgb white = C(0.85f, 0.85f, 0.82f), dark = C(0.06f, 0.06f, 0.07f);
  OfficeBuilder b{s, s->static_mesh, rng, white, dark, OfficeAddMaterials(s, rng, white, dark), kFirstStaticId};
  OfficeShell(b);
  OfficeBackWall(b);
  OfficeShelvesAndPlant(b);
  OfficeSideWallsAndPartitions(b);
  // Two desks with monitors, keyboards, mice, books, cups; a laptop on the left one.
  for (int d = 0; d < 2; ++d) {
    const float x0 = d == 0 ? -1.55f : 0.03f, x1 = d == 0 ? -0.03f : 1.55f, xc = 0.5f * (x0 + x1);
    OfficeDeskAndMonitors(b, d, x0, x1, xc);
    OfficeDeskItems(b, d, x0, x1, xc);
  }
  OfficeLaptop(b);
}

Mesh BuildChairMesh(Scene* s, uint64_t seed, int variant) {
  Rng rng(seed, "synth.scene.chair" + std::to_string(variant));
  const Rgb dark = C(0.05f, 0.05f, 0.05f);
  const int seat = s->AddMaterial(Mat(Pattern::kFabric, C(float(rng.Uniform(0.1, 0.5)), 0.12f, float(rng.Uniform(0.1, 0.4))),
                                      dark, dark, 1, rng));
  const int black = s->AddMaterial(Mat(Pattern::kFlat, C(0.06f, 0.06f, 0.07f), dark, dark, 1, rng));
  const int metal = s->AddMaterial(Mat(Pattern::kMetal, C(0.6f, 0.6f, 0.62f), dark, dark, 1, rng));
  Mesh m;
  m.AddBox(V(-0.24f, -0.24f, 0.42f), V(0.24f, 0.24f, 0.5f), seat, 0);
  m.AddBox(V(-0.27f, -0.22f, 0.56f), V(-0.2f, 0.22f, 1.02f), seat, 0);
  m.AddBox(V(-0.26f, -0.04f, 0.45f), V(-0.22f, 0.04f, 0.58f), black, 0);
  for (int side = -1; side <= 1; side += 2) {
    m.AddBox(V(-0.15f, 0.23f * float(side) - 0.02f, 0.5f), V(-0.11f, 0.23f * float(side) + 0.02f, 0.66f), black, 0);
    m.AddBox(V(-0.17f, 0.23f * float(side) - 0.03f, 0.66f), V(0.15f, 0.23f * float(side) + 0.03f, 0.69f), black, 0);
  }
  Mesh post;
  post.AddLimb(0.34f, 0.025f, 0.025f, 8, metal, 0);
  Eigen::Affine3f T = Eigen::Affine3f::Identity();
  T.translate(V(0, 0, 0.42f));
  m.Append(post, T);
  for (int k = 0; k < 5; ++k) {
    Mesh leg;
    leg.AddBox(V(0, -0.02f, 0.05f), V(0.3f, 0.02f, 0.09f), black, 0);
    leg.AddBox(V(0.26f, -0.025f, 0), V(0.31f, 0.025f, 0.05f), black, 0);
    Eigen::Affine3f R = Eigen::Affine3f::Identity();
    R.rotate(Eigen::AngleAxisf(1.2566371f * float(k) + 0.3f, V::UnitZ()));
    m.Append(leg, R);
  }
  return m;
}

Mesh BuildBoxMesh(Scene* s, uint64_t seed) {
  Rng rng(seed, "synth.scene.box");
  const int card = s->AddMaterial(Mat(Pattern::kCardboard, C(0.62f, 0.45f, 0.26f), C(0.75f, 0.68f, 0.5f), C(0.05f, 0.05f, 0.05f),
                                      0.3f, rng));
  Mesh m;
  m.AddBox(V(-0.22f, -0.17f, -0.15f), V(0.22f, 0.17f, 0.15f), card, 0);
  return m;
}

// The loop presets' extra wall decor (issue 34): printed posters over the wall behind the start
// view (y = -2.6) and over both side walls, so that a camera turning once around the room keeps
// enough ORB corners; its own random stream, so no other preset changes.
void AddLoopDecor(uint64_t seed, Scene* s) {
  Rng rng(seed, "synth.loop_decor");
  Mesh& m = s->static_mesh;
  const Rgb dark = C(0.06f, 0.06f, 0.07f);
  auto poster = [&](float k) {
    return s->AddMaterial(Mat(Pattern::kPrint, C(0.9f - 0.2f * k, 0.85f, 0.7f + 0.2f * k), dark,
                              C(0.2f + 0.6f * k, 0.3f, 0.8f - 0.5f * k), float(rng.Uniform(0.05, 0.12)), rng));
  };
  const float X0 = -2.8f, X1 = 2.8f, Y0 = -2.6f;
  for (int row = 0; row < 2; ++row)
    for (int col = 0; col < 5; ++col) {
      const float x = -2.6f + 1.05f * float(col), z = 0.45f + 0.9f * float(row);
      QuadY(&m, Y0 + 0.01f, x, x + 0.95f, z, z + 0.8f, poster(float((row + col) % 3) / 2.f), 0);
    }
  for (int row = 0; row < 2; ++row)
    for (int col = 0; col < 3; ++col) {
      const float y = -2.45f + 0.95f * float(col), z = 0.45f + 0.9f * float(row);
      QuadX(&m, X0 + 0.01f, y, y + 0.85f, z, z + 0.8f, poster(float((row + col + 1) % 3) / 2.f), 0);
      if (col != 1) QuadX(&m, X1 - 0.01f, y, y + 0.85f, z, z + 0.8f, poster(float((row + col + 2) % 3) / 2.f), 0);
    }
}

}  // namespace dynref::synth
