#include "dense/voxel_bricks.h"

#include "dense/filters.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/parallel.h"

namespace dynref::dense {
namespace {

int64_t FloorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

VoxelBricks::VoxelBricks(double leaf_m, double radius_m) {
  if (!(leaf_m > 0) || !(radius_m > 0)) throw std::invalid_argument("VoxelBricks: leaf and radius must be > 0");
  voxels_per_brick_ = static_cast<int64_t>(std::ceil(radius_m / leaf_m)) + 1;
  leaf_m_ = leaf_m;
}

VoxelKey VoxelBricks::BrickOf(const VoxelKey& v) const {
  return {FloorDiv(v[0], voxels_per_brick_), FloorDiv(v[1], voxels_per_brick_), FloorDiv(v[2], voxels_per_brick_)};
}

void VoxelBricks::Add(const VoxelKey& voxel, const std::array<float, 3>& pos) {
  const uint32_t b = bricks_.Insert(BrickOf(voxel));
  if (b == members_.size()) members_.emplace_back();
  where_.push_back({b, static_cast<uint32_t>(members_[b].size())});
  members_[b].push_back({pos[0], pos[1], pos[2], static_cast<uint32_t>(where_.size() - 1)});
}

void VoxelBricks::Move(uint32_t id, const std::array<float, 3>& pos) {
  Point& p = members_[where_[id].first][where_[id].second];
  p.x = pos[0], p.y = pos[1], p.z = pos[2];
}

const std::vector<VoxelBricks::Point>* VoxelBricks::Find(const VoxelKey& brick) const {
  const uint32_t b = bricks_.Find(brick);
  return b == KeyHash::kNone ? nullptr : &members_[b];
}

std::vector<double> CappedMeanKnnDistances(const VoxelBricks& queries, const std::vector<const VoxelBricks*>& others,
                                           int k, double cap_m, int threads) {
  if (k < 1) throw std::invalid_argument("CappedMeanKnnDistances: k must be >= 1");
  for (const VoxelBricks* o : others)
    if (o->voxels_per_brick() != queries.voxels_per_brick() || o->leaf_m() != queries.leaf_m())
      throw std::invalid_argument("CappedMeanKnnDistances: bricks of different size");
  const float cap2 = static_cast<float>(cap_m * cap_m);
  const size_t kk = static_cast<size_t>(k);
  std::vector<const VoxelBricks*> sets = {&queries};
  sets.insert(sets.end(), others.begin(), others.end());
  std::vector<double> out(queries.size());
  const double reach2 = (cap_m + 1e-4) * (cap_m + 1e-4);
  // A brick around the query brick: its points and its extent in metres, grown by 0.1 mm for the
  // float rounding of centroids on a voxel face. A brick farther than the search radius from a
  // query is skipped for it (nothing in it can be a neighbour within that radius).
  struct Segment {
    const VoxelBricks::Point* begin;
    const VoxelBricks::Point* end;
    double lo[3], hi[3];
  };
  const double brick_m = static_cast<double>(queries.voxels_per_brick()) * queries.leaf_m();
  // Chunks of bricks, one task each, with their own scratch; every point writes only out[id].
  constexpr uint32_t kChunk = 32;
  const uint32_t n_bricks = static_cast<uint32_t>(queries.bricks());
  ParallelFor(static_cast<int>((n_bricks + kChunk - 1) / kChunk), threads, [&](int chunk) {
    std::vector<float> near, far;
    std::vector<Segment> segments;
    const uint32_t chunk_end = std::min(n_bricks, (static_cast<uint32_t>(chunk) + 1) * kChunk);
    for (uint32_t b = static_cast<uint32_t>(chunk) * kChunk; b < chunk_end; ++b) {
      const VoxelKey& key = queries.brick_key(b);
      segments.clear();
      for (const VoxelBricks* set : sets)
        for (int64_t dx = -1; dx <= 1; ++dx)
          for (int64_t dy = -1; dy <= 1; ++dy)
            for (int64_t dz = -1; dz <= 1; ++dz) {
              const VoxelKey at = {key[0] + dx, key[1] + dy, key[2] + dz};
              const std::vector<VoxelBricks::Point>* pts = set->Find(at);
              if (pts == nullptr) continue;
              Segment seg{pts->data(), pts->data() + pts->size(), {}, {}};
              for (size_t a = 0; a < 3; ++a)
                seg.lo[a] = static_cast<double>(at[a]) * brick_m - 1e-4, seg.hi[a] = static_cast<double>(at[a] + 1) * brick_m + 1e-4;
              segments.push_back(seg);
            }
      const std::vector<VoxelBricks::Point>& own = queries.brick_members(b);
      for (const VoxelBricks::Point& self : own) {
        const float qx = self.x, qy = self.y, qz = self.z;
        const double q[3] = {qx, qy, qz};
        // One scan of the bricks within R; neighbours within 0.6 R kept apart: on a dense surface
        // the k nearest lie there (then only those are ranked; exact, since every point within R
        // is scanned).
        near.clear(), far.clear();
        const float inner2 = cap2 * 0.36f;
        for (const Segment& seg : segments) {
          double box2 = 0;
          for (int a = 0; a < 3; ++a) {
            const double e = q[a] < seg.lo[a] ? seg.lo[a] - q[a] : (q[a] > seg.hi[a] ? q[a] - seg.hi[a] : 0.0);
            box2 += e * e;
          }
          if (box2 > reach2) continue;
          for (const VoxelBricks::Point* p = seg.begin; p != seg.end; ++p) {
            // nanoflann's L2_Simple_Adaptor: float, dimensions in order.
            const float ex = qx - p->x, ey = qy - p->y, ez = qz - p->z;
            float d = ex * ex;
            d += ey * ey;
            d += ez * ez;
            if (d >= cap2 || p == &self) continue;
            (d < inner2 ? near : far).push_back(d);
          }
        }
        if (near.size() < kk) near.insert(near.end(), far.begin(), far.end());
        if (near.size() > kk) {
          std::nth_element(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(kk), near.end());
          near.resize(kk);
        }
        while (near.size() < kk) near.push_back(cap2);
        std::sort(near.begin(), near.end());
        out[self.id] = MeanOfAscendingDistances(near.data(), near.data() + kk);
      }
    }
  });
  return out;
}

}  // namespace dynref::dense
