#include "synth/raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynref::synth {

using Eigen::Vector2f;
using Eigen::Vector3f;

void Mesh::AddQuad(const Vector3f& p0, const Vector3f& p1, const Vector3f& p2, const Vector3f& p3,
                   int material, int instance, Vector2f uv0) {
  const int base = int(pos.size());
  pos.push_back(p0);
  pos.push_back(p1);
  pos.push_back(p2);
  pos.push_back(p3);
  const float lu = (p1 - p0).norm(), lv = (p3 - p0).norm();
  const Vector2f t0 = uv0, t1 = uv0 + Vector2f(lu, 0), t2 = uv0 + Vector2f(lu, lv), t3 = uv0 + Vector2f(0, lv);
  MeshTri a;
  a.a = base, a.b = base + 1, a.c = base + 2;
  a.uv[0] = t0, a.uv[1] = t1, a.uv[2] = t2;
  a.material = uint16_t(material), a.instance = uint16_t(instance);
  MeshTri b = a;
  b.a = base, b.b = base + 2, b.c = base + 3;
  b.uv[0] = t0, b.uv[1] = t2, b.uv[2] = t3;
  tris.push_back(a);
  tris.push_back(b);
}

void Mesh::AddBoxFront(const Vector3f& lo, const Vector3f& hi, int material, int front_material,
                       int instance, int front_axis_sign) {
  const float x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  // uv origins differ per face so that neighbouring faces do not repeat the same texture patch.
  AddQuad({x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1},
          front_axis_sign < 0 ? front_material : material, instance, {x0, z0});   // -y face
  AddQuad({x1, y1, z0}, {x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1},
          front_axis_sign > 0 ? front_material : material, instance, {x0 + 3.1f, z0});  // +y
  AddQuad({x0, y1, z0}, {x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, material, instance, {y0 + 1.7f, z0});
  AddQuad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}, material, instance, {y0 + 5.3f, z0});
  AddQuad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}, material, instance, {x0 + 7.9f, y0});
  AddQuad({x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}, {x0, y0, z0}, material, instance, {x0 + 2.3f, y0});
}

void Mesh::AddBox(const Vector3f& lo, const Vector3f& hi, int material, int instance) {
  AddBoxFront(lo, hi, material, material, instance, 0);
}

void Mesh::AddLimb(float length, float r_top, float r_bottom, int sides, int material, int instance,
                   float uv_u0) {
  const int base = int(pos.size());
  const float kPi = 3.14159265358979f;
  for (int i = 0; i < sides; ++i) {
    const float a = 2 * kPi * float(i) / float(sides);
    pos.emplace_back(r_top * std::cos(a), r_top * std::sin(a), 0.f);
    pos.emplace_back(r_bottom * std::cos(a), r_bottom * std::sin(a), -length);
  }
  pos.emplace_back(0.f, 0.f, 0.f);
  pos.emplace_back(0.f, 0.f, -length);
  const int ctop = base + 2 * sides, cbot = ctop + 1;
  const float circ = 2 * kPi * 0.5f * (r_top + r_bottom);
  for (int i = 0; i < sides; ++i) {
    const int j = (i + 1) % sides;
    const float u0 = uv_u0 + circ * float(i) / float(sides), u1 = uv_u0 + circ * float(i + 1) / float(sides);
    MeshTri t;
    t.material = uint16_t(material), t.instance = uint16_t(instance);
    t.a = base + 2 * i, t.b = base + 2 * i + 1, t.c = base + 2 * j + 1;
    t.uv[0] = {u0, 0.f}, t.uv[1] = {u0, -length}, t.uv[2] = {u1, -length};
    tris.push_back(t);
    t.a = base + 2 * i, t.b = base + 2 * j + 1, t.c = base + 2 * j;
    t.uv[0] = {u0, 0.f}, t.uv[1] = {u1, -length}, t.uv[2] = {u1, 0.f};
    tris.push_back(t);
    t.a = ctop, t.b = base + 2 * j, t.c = base + 2 * i;
    t.uv[0] = {0, 0}, t.uv[1] = {r_top, 0}, t.uv[2] = {0, r_top};
    tris.push_back(t);
    t.a = cbot, t.b = base + 2 * i + 1, t.c = base + 2 * j + 1;
    t.uv[0] = {0, 0}, t.uv[1] = {r_bottom, 0}, t.uv[2] = {0, r_bottom};
    tris.push_back(t);
  }
}

void Mesh::AddEllipsoid(const Vector3f& c, const Vector3f& r, int slices, int stacks, int material,
                        int instance, int top_material, float top_from_z) {
  const int base = int(pos.size());
  const float kPi = 3.14159265358979f;
  for (int s = 0; s <= stacks; ++s) {
    const float th = kPi * float(s) / float(stacks);  // 0 = top
    for (int i = 0; i <= slices; ++i) {
      const float ph = 2 * kPi * float(i) / float(slices);
      pos.emplace_back(c.x() + r.x() * std::sin(th) * std::cos(ph), c.y() + r.y() * std::sin(th) * std::sin(ph),
                       c.z() + r.z() * std::cos(th));
    }
  }
  const int row = slices + 1;
  for (int s = 0; s < stacks; ++s) {
    for (int i = 0; i < slices; ++i) {
      const int p00 = base + s * row + i, p01 = p00 + 1, p10 = p00 + row, p11 = p10 + 1;
      const float zc = 0.5f * (pos[p00].z() + pos[p10].z()) - c.z();
      MeshTri t;
      t.material = uint16_t(zc > top_from_z ? top_material : material);
      t.instance = uint16_t(instance);
      const float u0 = 2 * kPi * r.x() * float(i) / float(slices), u1 = 2 * kPi * r.x() * float(i + 1) / float(slices);
      const float v0 = kPi * r.z() * float(s) / float(stacks), v1 = kPi * r.z() * float(s + 1) / float(stacks);
      t.a = p00, t.b = p10, t.c = p11;
      t.uv[0] = {u0, v0}, t.uv[1] = {u0, v1}, t.uv[2] = {u1, v1};
      tris.push_back(t);
      t.a = p00, t.b = p11, t.c = p01;
      t.uv[0] = {u0, v0}, t.uv[1] = {u1, v1}, t.uv[2] = {u1, v0};
      tris.push_back(t);
    }
  }
}

void Mesh::Append(const Mesh& other, const Eigen::Affine3f& T) {
  const int base = int(pos.size());
  for (const auto& p : other.pos) pos.push_back(T * p);
  for (auto t : other.tris) {
    t.a += base, t.b += base, t.c += base;
    tris.push_back(t);
  }
}

void Mesh::Bounds(Vector3f* lo, Vector3f* hi) const {
  *lo = Vector3f::Constant(std::numeric_limits<float>::max());
  *hi = -*lo;
  for (const auto& p : pos) {
    *lo = lo->cwiseMin(p);
    *hi = hi->cwiseMax(p);
  }
}

namespace {

struct ClipVert {
  Vector3f p;  // camera frame
  float u, v;
};

// Sutherland-Hodgman against z >= near. in has 3 vertices, out up to 4.
int ClipNear(const ClipVert* in, ClipVert* out) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const ClipVert& a = in[i];
    const ClipVert& b = in[(i + 1) % 3];
    const bool ain = a.p.z() >= kNearPlaneM, bin = b.p.z() >= kNearPlaneM;
    if (ain) out[n++] = a;
    if (ain != bin) {
      const float s = (kNearPlaneM - a.p.z()) / (b.p.z() - a.p.z());
      ClipVert c;
      c.p = a.p + s * (b.p - a.p);
      c.p.z() = kNearPlaneM;
      c.u = a.u + s * (b.u - a.u);
      c.v = a.v + s * (b.v - a.v);
      out[n++] = c;
    }
  }
  return n;
}

struct ScreenVert {
  float x, y, w, uw, vw;  // pixel coords, 1/z, u/z, v/z
};

inline bool TopLeft(float ex, float ey) { return (ey < 0) || (ey == 0 && ex > 0); }

void RasterTri(const ScreenVert& a, const ScreenVert& b0, const ScreenVert& c0, int32_t face, GBuffer* gb) {
  ScreenVert b = b0, c = c0;
  float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(std::fabs(area) > 1e-9f)) return;
  if (area < 0) {
    std::swap(b, c);
    area = -area;
  }
  const int W = gb->width, H = gb->height;
  const int x0 = std::max(0, int(std::ceil(std::min({a.x, b.x, c.x}))));
  const int x1 = std::min(W - 1, int(std::floor(std::max({a.x, b.x, c.x}))));
  const int y0 = std::max(0, int(std::ceil(std::min({a.y, b.y, c.y}))));
  const int y1 = std::min(H - 1, int(std::floor(std::max({a.y, b.y, c.y}))));
  if (x0 > x1 || y0 > y1) return;
  // Edge i is opposite vertex i: E(x,y) = A x + B y + C, positive inside.
  const ScreenVert* v[3] = {&a, &b, &c};
  float A[3], B[3], C[3];
  bool tl[3];
  for (int i = 0; i < 3; ++i) {
    const ScreenVert& p = *v[(i + 1) % 3];
    const ScreenVert& q = *v[(i + 2) % 3];
    A[i] = p.y - q.y;
    B[i] = q.x - p.x;
    C[i] = p.x * q.y - p.y * q.x;
    tl[i] = TopLeft(q.x - p.x, q.y - p.y);
  }
  const float inv_area = 1.f / area;
  for (int y = y0; y <= y1; ++y) {
    const float fy = float(y);
    for (int x = x0; x <= x1; ++x) {
      const float fx = float(x);
      const float e0 = A[0] * fx + B[0] * fy + C[0];
      const float e1 = A[1] * fx + B[1] * fy + C[1];
      const float e2 = A[2] * fx + B[2] * fy + C[2];
      if (e0 < 0 || e1 < 0 || e2 < 0) continue;
      if ((e0 == 0 && !tl[0]) || (e1 == 0 && !tl[1]) || (e2 == 0 && !tl[2])) continue;
      const float l0 = e0 * inv_area, l1 = e1 * inv_area, l2 = 1.f - l0 - l1;
      const float w = l0 * a.w + l1 * b.w + l2 * c.w;
      if (!(w > 0)) continue;
      const float z = 1.f / w;
      const int idx = y * W + x;
      if (z >= gb->z[idx]) continue;
      gb->z[idx] = z;
      gb->face[idx] = face;
      gb->u[idx] = (l0 * a.uw + l1 * b.uw + l2 * c.uw) * z;
      gb->v[idx] = (l0 * a.vw + l1 * b.vw + l2 * c.vw) * z;
    }
  }
}

}  // namespace

void Rasterize(const Intrinsics& K, const SE3& T_cw, const std::vector<DrawItem>& items, GBuffer* gb) {
  const int W = K.width, H = K.height;
  gb->width = W, gb->height = H;
  gb->z.assign(size_t(W) * H, std::numeric_limits<float>::infinity());
  gb->face.assign(size_t(W) * H, -1);
  gb->u.assign(size_t(W) * H, 0.f);
  gb->v.assign(size_t(W) * H, 0.f);
  gb->faces.clear();
  std::vector<Vector3f> pc;
  for (const DrawItem& item : items) {
    const SE3 T_co = T_cw * item.T_wo;
    const Eigen::Matrix3f R = T_co.linear().cast<float>();
    const Vector3f t = T_co.translation().cast<float>();
    const Eigen::Matrix3f R_wc = T_cw.linear().transpose().cast<float>();
    const Mesh& mesh = *item.mesh;
    pc.resize(mesh.pos.size());
    for (size_t i = 0; i < mesh.pos.size(); ++i) pc[i] = R * mesh.pos[i] + t;
    for (const MeshTri& tri : mesh.tris) {
      const Vector3f& pa = pc[tri.a];
      const Vector3f& pb = pc[tri.b];
      const Vector3f& pcv = pc[tri.c];
      if (pa.z() < kNearPlaneM && pb.z() < kNearPlaneM && pcv.z() < kNearPlaneM) continue;
      Vector3f n_c = (pb - pa).cross(pcv - pa);
      const float nn = n_c.norm();
      if (!(nn > 1e-12f)) continue;
      n_c /= nn;
      if (n_c.dot(pa) > 0) n_c = -n_c;  // two-sided: face the camera
      FaceRecord rec;
      rec.n_w = R_wc * n_c;
      rec.material = tri.material;
      rec.instance = uint16_t(item.instance_override > 0 ? item.instance_override : tri.instance);
      rec.part = item.part;
      const int32_t face = int32_t(gb->faces.size());
      gb->faces.push_back(rec);
      const ClipVert in[3] = {{pa, tri.uv[0].x(), tri.uv[0].y()},
                              {pb, tri.uv[1].x(), tri.uv[1].y()},
                              {pcv, tri.uv[2].x(), tri.uv[2].y()}};
      ClipVert poly[4];
      const int n = ClipNear(in, poly);
      ScreenVert sv[4];
      for (int i = 0; i < n; ++i) {
        const float w = 1.f / poly[i].p.z();
        sv[i] = {K.fx * poly[i].p.x() * w + K.cx, K.fy * poly[i].p.y() * w + K.cy, w, poly[i].u * w,
                 poly[i].v * w};
      }
      for (int i = 1; i + 1 < n; ++i) RasterTri(sv[0], sv[i], sv[i + 1], face, gb);
    }
  }
}

}  // namespace dynref::synth
