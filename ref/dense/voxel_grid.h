// Voxel grid of the dense maps (PCL VoxelGrid semantics) on a flat, hashed store: one point per
// occupied cubic voxel of side leaf_m, at the centroid of its points; colour = rounded mean
// colour; class_id = most frequent class of the voxel (ties: smallest id; -1 counts like any id).
// Voxel key = floor(p / leaf_m) per axis. Output (Cloud, Keys) is ordered by key (x, then y,
// then z); accumulation follows the add order, so Cloud() after Add(a), Add(b) equals
// VoxelDownsample(a + b) bit for bit. The hash table is only looked up, never iterated into a
// result (voxel indices are the insertion order), so everything is deterministic.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "dense/point_cloud.h"

namespace dynref::dense {

using VoxelKey = std::array<int64_t, 3>;  // ordered lexicographically (KeyLess = std::array operator<)

// A growing array in fixed chunks of 2^16 elements: no reallocation copies and at most one
// partly used chunk, where a std::vector doubling its capacity holds up to twice what it uses
// (a dense room map has millions of voxels; issue 18, peak memory).
template <class T>
class ChunkedVector {
 public:
  size_t size() const { return size_; }
  T& operator[](size_t i) { return (*chunks_[i >> kShift])[i & kMask]; }
  const T& operator[](size_t i) const { return (*chunks_[i >> kShift])[i & kMask]; }
  T& emplace_back() {
    if ((size_ & kMask) == 0) chunks_.push_back(std::make_unique<std::array<T, kChunk>>());
    return (*this)[size_++];
  }
  void push_back(const T& v) { emplace_back() = v; }
  void resize_filled(size_t n, const T& v) {  // grow to n, new elements = v
    while (size_ < n) push_back(v);
  }

 private:
  static constexpr int kShift = 16;
  static constexpr size_t kChunk = size_t{1} << kShift, kMask = kChunk - 1;
  std::vector<std::unique_ptr<std::array<T, kChunk>>> chunks_;
  size_t size_ = 0;
};

inline bool KeyEqual(const VoxelKey& a, const VoxelKey& b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }
inline bool KeyLess(const VoxelKey& a, const VoxelKey& b) {
  return a[0] != b[0] ? a[0] < b[0] : (a[1] != b[1] ? a[1] < b[1] : a[2] < b[2]);
}

// Open-addressing (linear probing) map from a key to its dense index 0, 1, 2, ... in insertion
// order. No iteration over slots is exposed.
class KeyHash {
 public:
  static constexpr uint32_t kNone = 0xffffffffu;
  uint32_t Find(const VoxelKey& key) const;
  // Index of key, inserting it (index = size() before the call) when absent.
  uint32_t Insert(const VoxelKey& key);
  size_t size() const { return keys_.size(); }
  const VoxelKey& key(uint32_t index) const { return keys_[index]; }

 private:
  static uint64_t Hash(const VoxelKey& key);
  void Rehash(size_t slots);
  std::vector<VoxelKey> keys_;
  // Slot = index | (upper 32 bits of the key's hash) << 32, so most probes of a different key are
  // told apart without reading its key; kEmpty = empty. Size a power of two, load <= 1/2.
  static constexpr uint64_t kEmpty = ~uint64_t{0};
  std::vector<uint64_t> slots_;
};

// Voxel key -> dense index (insertion order), two-level as in voxel hashing (KinectFusion-style
// dense mapping): bricks of 4 x 4 x 4 voxels in a KeyHash, each brick a direct table of its 64
// cells. Points of one surface, added in scan order, mostly hit the brick of the previous point,
// so a look-up costs a cached table read instead of a cache miss per voxel (issue 18).
class VoxelKeyIndex {
 public:
  static constexpr uint32_t kNone = KeyHash::kNone;
  uint32_t Find(const VoxelKey& key) const;
  uint32_t Insert(const VoxelKey& key);  // as KeyHash::Insert
  size_t size() const { return keys_.size(); }
  const VoxelKey& key(uint32_t index) const { return keys_[index]; }

 private:
  static constexpr int kCells = 64;
  // Floor division / modulo by 4 (two's complement: arithmetic shift and mask).
  static VoxelKey BrickOf(const VoxelKey& k) { return {k[0] >> 2, k[1] >> 2, k[2] >> 2}; }
  static size_t CellOf(const VoxelKey& k) { return static_cast<size_t>((k[0] & 3) << 4 | (k[1] & 3) << 2 | (k[2] & 3)); }
  uint32_t BrickId(const VoxelKey& brick) const;  // via the memo of the last brick looked up
  KeyHash bricks_;
  ChunkedVector<uint32_t> cells_;  // kCells per brick, kNone = empty
  ChunkedVector<VoxelKey> keys_;
  // The last brick found (a look-up cache only: never changes a result).
  mutable VoxelKey memo_key_{};
  mutable uint32_t memo_id_ = kNone;
};

// The points of one voxel: sums of position and colour, count, class votes (up to 3 distinct
// classes inline, a voxel rarely sees more; the rest in `more`).
struct VoxelAccumulator {
  double x = 0, y = 0, z = 0;
  uint32_t r = 0, g = 0, b = 0;  // exact integer sums (a voxel holds < 2^24 points)
  int32_t n = 0;
  int16_t cls[3] = {0, 0, 0};
  int32_t cls_count[3] = {0, 0, 0};
  uint8_t n_cls = 0;
  std::unique_ptr<std::map<int16_t, int32_t>> more;
  void Add(const ColoredPoint& p);
  // The points of o added in one step (sums and votes merged).
  void Merge(const VoxelAccumulator& o);
  ColoredPoint Centroid() const;
  std::array<float, 3> Position() const;  // Centroid()'s x, y, z

 private:
  void Vote(int16_t class_id, int32_t count);
};

// The voxels of one cloud in key order, built by sorting (a stable LSD radix sort on packed keys
// when the cloud's key ranges fit in 64 bits, else a stable sort), as PCL's VoxelGrid does:
// points of a voxel are accumulated in input order. Non-finite points are skipped.
struct SortedVoxels {
  std::vector<VoxelKey> keys;
  std::vector<VoxelAccumulator> acc;
  size_t size() const { return keys.size(); }
};
SortedVoxels SortIntoVoxels(const PointCloud& in, double leaf_m);

class VoxelGrid {
 public:
  using Key = VoxelKey;
  explicit VoxelGrid(double leaf_m);  // std::invalid_argument unless leaf_m > 0
  void Add(const PointCloud& points);  // non-finite points are skipped
  Key KeyOf(const ColoredPoint& p) const;  // floor(p / leaf_m) per axis (finite points)
  std::vector<Key> Keys() const;           // key order (the order of Cloud())
  PointCloud Cloud() const;                // key order, as VoxelDownsample
  size_t size() const { return index_.size(); }
  // Voxel index of a key (insertion order) or VoxelKeyIndex::kNone.
  uint32_t Find(const Key& key) const { return index_.Find(key); }
  const Key& KeyAt(uint32_t index) const { return index_.key(index); }
  ColoredPoint CentroidAt(uint32_t index) const { return acc_[index].Centroid(); }
  std::array<float, 3> PositionAt(uint32_t index) const { return acc_[index].Position(); }
  // Adds a voxel's points (an accumulator of the same leaf) in one step; returns its index.
  uint32_t Merge(const Key& key, const VoxelAccumulator& points);

 private:
  std::vector<uint32_t> SortedIndices() const;
  double leaf_m_, inv_;
  VoxelKeyIndex index_;
  ChunkedVector<VoxelAccumulator> acc_;
};

// The voxel grid of one cloud (SortIntoVoxels' centroids, key order).
PointCloud VoxelDownsample(const PointCloud& in, double leaf_m);

}  // namespace dynref::dense
