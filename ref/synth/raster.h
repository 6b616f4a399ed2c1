// Deterministic single-threaded CPU rasterizer: triangles with a z-buffer, near-plane clipping and
// perspective-correct (u, v) interpolation (1/z, u/z, v/z are affine in screen space). Renders a
// G-buffer (depth, face, u, v); shading is done once per pixel afterwards (synth/shading.h).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/intrinsics.h"
#include "core/se3.h"

namespace dynref::synth {

struct MeshTri {
  int a = 0, b = 0, c = 0;                 // vertex indices
  Eigen::Vector2f uv[3];                   // texture coordinates in metres on the surface
  uint16_t material = 0;
  uint16_t instance = 0;                   // scene-wide instance id (0 = background structure)
};

struct Mesh {
  std::vector<Eigen::Vector3f> pos;        // object-frame vertices (metres)
  std::vector<MeshTri> tris;
  // Quad p0..p3 (counter-clockwise seen from the front) with uv in metres along p0->p1, p0->p3.
  void AddQuad(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
               const Eigen::Vector3f& p3, int material, int instance, Eigen::Vector2f uv0 = {0, 0});
  // Axis-aligned box [lo, hi] in the object frame (6 quads, uv in metres).
  void AddBox(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int material, int instance);
  // Same box with a separate material for the +y face (e.g. a book cover, a screen).
  void AddBoxFront(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int material,
                   int front_material, int instance, int front_axis_sign);
  // Prism along -z from z=0 to z=-length with `sides` sides, radius r_top -> r_bottom, capped.
  void AddLimb(float length, float r_top, float r_bottom, int sides, int material, int instance,
               float uv_u0 = 0.f);
  // Low-poly ellipsoid centred at c with radii r (latitude/longitude grid).
  void AddEllipsoid(const Eigen::Vector3f& c, const Eigen::Vector3f& r, int slices, int stacks,
                    int material, int instance, int top_material, float top_from_z);
  void Append(const Mesh& other, const Eigen::Affine3f& T);
  void Bounds(Eigen::Vector3f* lo, Eigen::Vector3f* hi) const;
};

// One rigid piece drawn at a pose. `part` is a scene-wide index used for motion flags.
struct DrawItem {
  const Mesh* mesh = nullptr;
  SE3 T_wo = SE3::Identity();              // world_from_object
  int part = 0;
  int instance_override = 0;               // > 0 replaces the per-triangle instance id
};

// The renderer rasterises in float (generated sequences are bit-identical across versions).
using Intrinsics = PinholeIntrinsics<float>;

struct FaceRecord {
  Eigen::Vector3f n_w;                     // unit world normal, flipped to face the camera
  uint16_t material = 0;
  uint16_t instance = 0;
  int part = 0;
};

struct GBuffer {
  int width = 0, height = 0;
  std::vector<float> z;                    // camera-frame depth (m), +inf = nothing
  std::vector<int32_t> face;               // index into faces, -1 = nothing
  std::vector<float> u, v;
  std::vector<FaceRecord> faces;
};

constexpr float kNearPlaneM = 0.05f;

// Renders every item seen from T_cw (camera_from_world, OpenCV camera axes) into gb.
void Rasterize(const Intrinsics& K, const SE3& T_cw, const std::vector<DrawItem>& items, GBuffer* gb);

}  // namespace dynref::synth
