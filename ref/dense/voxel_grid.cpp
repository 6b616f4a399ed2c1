#include "dense/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace dynref::dense {
namespace {

uint64_t Mix(uint64_t h) {  // splitmix64 finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

uint8_t RoundColour(uint32_t sum, int n) {
  return static_cast<uint8_t>(std::clamp(std::lround(static_cast<double>(sum) / n), 0L, 255L));
}

}  // namespace

uint64_t KeyHash::Hash(const VoxelKey& key) {
  return Mix(static_cast<uint64_t>(key[0]) * 0x9e3779b97f4a7c15ULL ^ Mix(static_cast<uint64_t>(key[1]) + 0x632be59bd9b4e019ULL) ^
             (static_cast<uint64_t>(key[2]) << 1));
}

uint32_t KeyHash::Find(const VoxelKey& key) const {
  if (slots_.empty()) return kNone;
  const uint64_t h = Hash(key), tag = h >> 32 << 32, mask = slots_.size() - 1;
  for (size_t s = static_cast<size_t>(h) & mask;; s = (s + 1) & mask) {
    const uint64_t slot = slots_[s];
    if (slot == kEmpty) return kNone;
    const uint32_t i = static_cast<uint32_t>(slot);
    if ((slot >> 32 << 32) == tag && KeyEqual(keys_[i], key)) return i;
  }
}

uint32_t KeyHash::Insert(const VoxelKey& key) {
  if (2 * (keys_.size() + 1) > slots_.size()) Rehash(std::max<size_t>(64, slots_.size() * 2));
  const uint64_t h = Hash(key), tag = h >> 32 << 32, mask = slots_.size() - 1;
  for (size_t s = static_cast<size_t>(h) & mask;; s = (s + 1) & mask) {
    const uint64_t slot = slots_[s];
    if (slot == kEmpty) {
      if (keys_.size() >= kNone) throw std::length_error("KeyHash: more than 2^32 - 1 keys");
      const uint32_t i = static_cast<uint32_t>(keys_.size());
      slots_[s] = tag | i;
      keys_.push_back(key);
      return i;
    }
    const uint32_t i = static_cast<uint32_t>(slot);
    if ((slot >> 32 << 32) == tag && KeyEqual(keys_[i], key)) return i;
  }
}

void KeyHash::Rehash(size_t slots) {
  slots_.assign(slots, kEmpty);
  const uint64_t mask = slots_.size() - 1;
  for (uint32_t i = 0; i < keys_.size(); ++i) {
    const uint64_t h = Hash(keys_[i]);
    size_t s = static_cast<size_t>(h) & mask;
    while (slots_[s] != kEmpty) s = (s + 1) & mask;
    slots_[s] = (h >> 32 << 32) | i;
  }
}

uint32_t VoxelKeyIndex::BrickId(const VoxelKey& brick) const {
  if (memo_id_ != kNone && KeyEqual(memo_key_, brick)) return memo_id_;
  const uint32_t b = bricks_.Find(brick);
  if (b != kNone) memo_key_ = brick, memo_id_ = b;
  return b;
}

uint32_t VoxelKeyIndex::Find(const VoxelKey& key) const {
  const uint32_t b = BrickId(BrickOf(key));
  return b == kNone ? kNone : cells_[b * size_t{kCells} + CellOf(key)];
}

uint32_t VoxelKeyIndex::Insert(const VoxelKey& key) {
  const VoxelKey brick = BrickOf(key);
  uint32_t b = BrickId(brick);
  if (b == kNone) b = bricks_.Insert(brick), memo_key_ = brick, memo_id_ = b;
  if (b * size_t{kCells} == cells_.size()) cells_.resize_filled(cells_.size() + kCells, kNone);
  uint32_t& cell = cells_[b * size_t{kCells} + CellOf(key)];
  if (cell == kNone) {
    if (keys_.size() >= kNone) throw std::length_error("VoxelKeyIndex: more than 2^32 - 1 voxels");
    cell = static_cast<uint32_t>(keys_.size());
    keys_.push_back(key);
  }
  return cell;
}


void VoxelAccumulator::Vote(int16_t class_id, int32_t count) {
  for (int j = 0; j < n_cls; ++j)
    if (cls[j] == class_id) {
      cls_count[j] += count;
      return;
    }
  if (n_cls < 3) {
    cls[n_cls] = class_id;
    cls_count[n_cls] = count;
    ++n_cls;
    return;
  }
  if (!more) more = std::make_unique<std::map<int16_t, int32_t>>();
  (*more)[class_id] += count;
}

void VoxelAccumulator::Add(const ColoredPoint& p) {
  x += p.x, y += p.y, z += p.z;
  r += p.r, g += p.g, b += p.b;
  ++n;
  Vote(p.class_id, 1);
}

void VoxelAccumulator::Merge(const VoxelAccumulator& o) {
  x += o.x, y += o.y, z += o.z;
  r += o.r, g += o.g, b += o.b;
  n += o.n;
  for (int j = 0; j < o.n_cls; ++j) Vote(o.cls[j], o.cls_count[j]);
  if (o.more)
    for (const auto& [c, count] : *o.more) Vote(c, count);
}

std::array<float, 3> VoxelAccumulator::Position() const {
  return {static_cast<float>(x / n), static_cast<float>(y / n), static_cast<float>(z / n)};
}

ColoredPoint VoxelAccumulator::Centroid() const {
  ColoredPoint p;
  const std::array<float, 3> pos = Position();
  p.x = pos[0], p.y = pos[1], p.z = pos[2];
  p.r = RoundColour(r, n);
  p.g = RoundColour(g, n);
  p.b = RoundColour(b, n);
  // Most frequent class, ties: smallest id.
  int best = std::numeric_limits<int>::max(), best_count = -1;
  const auto consider = [&](int c, int count) {
    if (count > best_count || (count == best_count && c < best)) best = c, best_count = count;
  };
  for (int j = 0; j < n_cls; ++j) consider(cls[j], cls_count[j]);
  if (more)
    for (const auto& [c, count] : *more) consider(c, count);
  p.class_id = static_cast<int16_t>(best);
  return p;
}

namespace {

VoxelKey KeyOfPoint(const ColoredPoint& p, double inv) {
  return {static_cast<int64_t>(std::floor(p.x * inv)), static_cast<int64_t>(std::floor(p.y * inv)),
          static_cast<int64_t>(std::floor(p.z * inv))};
}

int BitsFor(uint64_t range) {  // bits to hold 0 .. range
  int bits = 0;
  while (bits < 64 && (range >> bits) != 0) ++bits;
  return bits;
}

// Stable LSD radix sort of (packed key, point index) by key, 11 bits per pass.
void RadixSort(std::vector<std::pair<uint64_t, uint32_t>>& v, int bits) {
  constexpr int kDigit = 11;
  std::vector<std::pair<uint64_t, uint32_t>> tmp(v.size());
  std::vector<size_t> count(size_t{1} << kDigit);
  for (int shift = 0; shift < bits; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0);
    for (const auto& e : v) ++count[(e.first >> shift) & ((1u << kDigit) - 1)];
    size_t sum = 0;
    for (size_t& c : count) {
      const size_t here = c;
      c = sum;
      sum += here;
    }
    for (const auto& e : v) tmp[count[(e.first >> shift) & ((1u << kDigit) - 1)]++] = e;
    v.swap(tmp);
  }
}

}  // namespace

SortedVoxels SortIntoVoxels(const PointCloud& in, double leaf_m) {
  if (!(leaf_m > 0)) throw std::invalid_argument("voxel leaf_m must be > 0");
  const double inv = 1.0 / leaf_m;
  const auto finite = [](const ColoredPoint& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
  // Key ranges of the finite points.
  VoxelKey lo{}, hi{};
  size_t n = 0;
  for (const ColoredPoint& p : in) {
    if (!finite(p)) continue;
    const VoxelKey k = KeyOfPoint(p, inv);
    if (n++ == 0) lo = hi = k;
    for (size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], k[a]), hi[a] = std::max(hi[a], k[a]);
  }
  const auto offset = [&](const VoxelKey& k, size_t a) {  // k[a] - lo[a] >= 0, without signed overflow
    return static_cast<uint64_t>(k[a]) - static_cast<uint64_t>(lo[a]);
  };
  const int bx = BitsFor(offset(hi, 0)), by = BitsFor(offset(hi, 1)), bz = BitsFor(offset(hi, 2));
  // (packed key, point index) in key order, stable (equal keys keep input order).
  std::vector<std::pair<uint64_t, uint32_t>> order;
  order.reserve(n);
  if (bx + by + bz <= 64) {
    // Packed (x, y, z) offsets from the minimum: integer order = lexicographic key order.
    for (uint32_t i = 0; i < in.size(); ++i) {
      if (!finite(in[i])) continue;
      const VoxelKey k = KeyOfPoint(in[i], inv);
      const uint64_t px = offset(k, 0), py = offset(k, 1), pz = offset(k, 2);
      order.emplace_back((bx ? px << (by + bz) : 0) | (by ? py << bz : 0) | pz, i);
    }
    RadixSort(order, bx + by + bz);
  } else {  // wide clouds (never a keyframe or a room): rank by a stable sort of the keys
    std::vector<std::pair<VoxelKey, uint32_t>> keyed;
    keyed.reserve(n);
    for (uint32_t i = 0; i < in.size(); ++i)
      if (finite(in[i])) keyed.emplace_back(KeyOfPoint(in[i], inv), i);
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return KeyLess(a.first, b.first); });
    uint64_t rank = 0;
    for (size_t j = 0; j < keyed.size(); ++j) {
      if (j > 0 && !KeyEqual(keyed[j - 1].first, keyed[j].first)) ++rank;
      order.emplace_back(rank, keyed[j].second);
    }
  }
  size_t voxels = 0;
  for (size_t j = 0; j < order.size(); ++j) voxels += j == 0 || order[j].first != order[j - 1].first;
  SortedVoxels out;
  out.keys.reserve(voxels);
  out.acc.resize(voxels);
  size_t v = 0;
  for (size_t j = 0; j < order.size(); ++j) {
    const ColoredPoint& p = in[order[j].second];
    if (j == 0 || order[j].first != order[j - 1].first) {
      if (j > 0) ++v;
      out.keys.push_back(KeyOfPoint(p, inv));
    }
    out.acc[v].Add(p);
  }
  return out;
}

VoxelGrid::VoxelGrid(double leaf_m) : leaf_m_(leaf_m), inv_(1.0 / leaf_m) {
  if (!(leaf_m > 0)) throw std::invalid_argument("voxel leaf_m must be > 0");
}

VoxelGrid::Key VoxelGrid::KeyOf(const ColoredPoint& p) const { return KeyOfPoint(p, inv_); }

void VoxelGrid::Add(const PointCloud& in) {
  for (const ColoredPoint& p : in) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    const uint32_t i = index_.Insert(KeyOf(p));
    if (i == acc_.size()) acc_.emplace_back();
    acc_[i].Add(p);
  }
}

uint32_t VoxelGrid::Merge(const Key& key, const VoxelAccumulator& points) {
  const uint32_t i = index_.Insert(key);
  if (i == acc_.size()) acc_.emplace_back();
  acc_[i].Merge(points);
  return i;
}

std::vector<uint32_t> VoxelGrid::SortedIndices() const {
  std::vector<uint32_t> order(index_.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return KeyLess(index_.key(a), index_.key(b)); });
  return order;  // keys are unique: the order is total
}

std::vector<VoxelGrid::Key> VoxelGrid::Keys() const {
  std::vector<Key> out;
  out.reserve(index_.size());
  for (uint32_t i : SortedIndices()) out.push_back(index_.key(i));
  return out;
}

PointCloud VoxelGrid::Cloud() const {
  PointCloud out;
  out.reserve(index_.size());
  for (uint32_t i : SortedIndices()) out.push_back(acc_[i].Centroid());
  return out;
}

PointCloud VoxelDownsample(const PointCloud& in, double leaf_m) {
  const SortedVoxels voxels = SortIntoVoxels(in, leaf_m);
  PointCloud out;
  out.reserve(voxels.size());
  for (const VoxelAccumulator& a : voxels.acc) out.push_back(a.Centroid());
  return out;
}

}  // namespace dynref::dense
