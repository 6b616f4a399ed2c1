// dynref_trace.hpp -- a dependency-free, single-header writer of dynref trace schema 3
// (ref/trace/README.md), for code outside dynref: an ORB-SLAM3 fork, a GPU pipeline, anything in
// C++17 that wants its per-feature probabilities, residuals and decisions diffed against the
// dynref oracle with `dynref diff ORACLE_RUN your.dtr`. Standard library only; copy this file.
//
//   dynref_trace::Writer w("run.dtr", dynref_trace::Level::kFull, {{"method", "my-slam"}});
//   w.Frame(0, 1305031102.175304);
//   w.Count("extract", "keypoints", 1000);
//   w.Prob("my.epipolar", dynref_trace::Kind::kFeature, "f0.17", {{"d_px", 0.4}}, 0.0, 0.1);
//   w.Decision("my.epipolar", dynref_trace::Kind::kFeature, "f0.17", true, "below-threshold");
//   w.Close("complete");  // writes the footer; the file appears under its name only now
//
// Errors (cannot open, write failed, use after Close) throw std::runtime_error. The file is
// written to "<path>.tmp" and renamed on Close(), so an unfinished trace never looks complete.
// Canonical entity ids, kinds and call ids: ref/trace/README.md ("Body records").
#pragma once
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dynref_trace {

enum class Level : uint8_t { kFrames = 1, kFull = 2 };
enum class Kind : uint8_t {
  kFeature = 0, kMapPoint = 1, kKeyFrame = 2, kLineSample = 3, kPlane = 4, kInstanceMask = 5,
  kPixelRegion = 6, kFrame = 7,
};

// CRC-32C (Castagnoli, reflected 0x82F63B78); Crc32c(0, "123456789", 9) == 0xE3069283.
inline uint32_t Crc32cUpdate(uint32_t crc, const void* data, size_t n) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t b = 0; b < 256; ++b) {
      uint32_t c = b;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? (c >> 1) ^ 0x82F63B78u : c >> 1;
      t[b] = c;
    }
    return t;
  }();
  const auto* p = static_cast<const uint8_t*>(data);
  uint32_t c = ~crc;
  for (size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xFF] ^ (c >> 8);
  return ~c;
}

constexpr uint32_t kSchemaVersion = 3;  // 3: OBS carries associated_map_point_id

class Writer {
 public:
  Writer(const std::string& path, Level level, const std::vector<std::pair<std::string, std::string>>& header)
      : path_(path), tmp_(path + ".tmp"), level_(level) {
    file_ = std::fopen(tmp_.c_str(), "wb");
    if (file_ == nullptr) throw std::runtime_error("dynref_trace: cannot open " + tmp_);
    buf_.append("DYNTRACE", 8);
    U32(kSchemaVersion);
    buf_.push_back(char(level));
    buf_.append(3, '\0');
    Varint(header.size());
    for (const auto& [k, v] : header) Str(k), Str(v);
    U32(Crc32cUpdate(0, buf_.data(), buf_.size()));  // preamble + header
    Flush(false);
    group_start_ = written_;
  }
  ~Writer() {
    if (file_ != nullptr) {  // never closed: leave no file under the final name
      std::fclose(file_);
      std::remove(tmp_.c_str());
    }
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Starts frame `frame` (rgb timestamp in seconds); records until the next Frame belong to it.
  void Frame(int64_t frame, double timestamp) {
    Open();
    EndGroup();
    group_frame_ = frame;
    in_group_ = true;
    Tag(0x02);
    Svarint(frame);
    F64(timestamp);
  }
  // which: "initial" | "final"; T_wc: rows 0..2 of the 4x4 world_from_camera, row-major.
  void Pose(const std::string& which, const std::array<double, 12>& T_wc) {
    const uint64_t w = Intern(which);
    Tag(0x03);
    Varint(w);
    for (double v : T_wc) F64(v);
  }
  void Count(const std::string& stage, const std::string& name, int64_t value) {
    const uint64_t s = Intern(stage), n = Intern(name);
    Tag(0x04);
    Varint(s);
    Varint(n);
    Svarint(value);
  }
  // Full level only (ignored at kFrames), as every record below.
  // map_point_id: final inlier association (-1 none); associated_map_point_id: the map point the
  // feature was associated with when the stages saw it, also when excluded or an outlier (-1 never).
  void Obs(int64_t feature_index, int64_t map_point_id, int64_t associated_map_point_id, double u, double v,
           double depth_m, int64_t octave, uint64_t descriptor_hash) {
    if (level_ != Level::kFull) return;
    Tag(0x05);
    Svarint(feature_index);
    Svarint(map_point_id);
    Svarint(associated_map_point_id);
    F64(u), F64(v), F64(depth_m);
    Svarint(octave);
    U64(descriptor_hash);
  }
  // Without a separate association (what schema 2 wrote): associated = map_point_id.
  void Obs(int64_t feature_index, int64_t map_point_id, double u, double v, double depth_m, int64_t octave,
           uint64_t descriptor_hash) {
    Obs(feature_index, map_point_id, map_point_id, u, v, depth_m, octave, descriptor_hash);
  }
  // before/after: probability that the entity is dynamic.
  void Prob(const std::string& stage, Kind kind, const std::string& entity,
            const std::vector<std::pair<std::string, double>>& inputs, double before, double after) {
    if (level_ != Level::kFull) return;
    const uint64_t s = Intern(stage);
    std::vector<uint64_t> ids;
    for (const auto& in : inputs) ids.push_back(Intern(in.first));
    Tag(0x06);
    Varint(s);
    buf_.push_back(char(kind));
    Str(entity);
    Varint(inputs.size());
    for (size_t i = 0; i < inputs.size(); ++i) Varint(ids[i]), F64(inputs[i].second);
    F64(before), F64(after);
  }
  void Residual(const std::string& call_id, const std::string& residual_kind, const std::string& observation_id,
                const std::vector<double>& start, const std::vector<double>& end, double information, double weight,
                double robust_loss, double chi2, bool inlier) {
    if (level_ != Level::kFull) return;
    const uint64_t c = Intern(call_id), k = Intern(residual_kind);
    Tag(0x07);
    Varint(c);
    Varint(k);
    Str(observation_id);
    Varint(start.size());
    for (double v : start) F64(v);
    Varint(end.size());
    for (double v : end) F64(v);
    F64(information), F64(weight), F64(robust_loss), F64(chi2);
    buf_.push_back(char(inlier ? 1 : 0));
  }
  void Decision(const std::string& stage, Kind kind, const std::string& entity, bool kept, const std::string& reason) {
    if (level_ != Level::kFull) return;
    const uint64_t s = Intern(stage), r = Intern(reason);
    Tag(0x08);
    Varint(s);
    buf_.push_back(char(kind));
    Str(entity);
    buf_.push_back(char(kept ? 1 : 0));
    Varint(r);
  }
  // Footer (frame index, string table, checksums), trailer, rename onto the final path.
  void Close(const std::string& end_state = "complete") {
    Open();
    EndGroup();
    Flush(false);
    const uint64_t footer = written_;
    buf_.push_back(char(0x7F));
    Varint(records_);
    Str(end_state);
    Varint(groups_.size());
    for (const Group& g : groups_) Svarint(g.frame), Varint(g.offset), Varint(g.records), U32(g.crc);
    Varint(table_.size());
    for (const std::string& s : table_) Str(s);
    U32(Crc32cUpdate(0, buf_.data(), buf_.size()));  // the footer so far
    U64(footer);
    buf_.append("DYNTREND", 8);
    Flush(false);
    const bool ok = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || std::rename(tmp_.c_str(), path_.c_str()) != 0) {
      std::remove(tmp_.c_str());
      throw std::runtime_error("dynref_trace: cannot finish " + path_);
    }
  }

 private:
  struct Group {
    int64_t frame;
    uint64_t offset, records;
    uint32_t crc;
  };
  void Open() const {
    if (file_ == nullptr) throw std::runtime_error("dynref_trace: writer already closed");
  }
  // A record starts: it counts in the current group (group -1 opens at the first body byte).
  void Tag(uint8_t tag) {
    Open();
    if (!in_group_) in_group_ = true, group_frame_ = -1;
    buf_.push_back(char(tag));
    ++group_records_;
    ++records_;
    if (buf_.size() >= (1u << 20)) Flush(true);
  }
  void EndGroup() {
    if (!in_group_) return;
    Flush(true);
    groups_.push_back({group_frame_, group_start_, group_records_, group_crc_});
    in_group_ = false;
    group_start_ = written_;
    group_records_ = 0;
    group_crc_ = 0;
  }
  void Flush(bool into_group) {
    if (buf_.empty()) return;
    if (into_group) group_crc_ = Crc32cUpdate(group_crc_, buf_.data(), buf_.size());
    if (std::fwrite(buf_.data(), 1, buf_.size(), file_) != buf_.size())
      throw std::runtime_error("dynref_trace: write failed on " + tmp_);
    written_ += buf_.size();
    buf_.clear();
  }
  uint64_t Intern(const std::string& s) {
    Open();
    const auto it = ids_.find(s);
    if (it != ids_.end()) return it->second;
    if (!in_group_) in_group_ = true, group_frame_ = -1;
    const uint64_t id = table_.size();
    ids_.emplace(s, id);
    table_.push_back(s);
    buf_.push_back(char(0x01));  // STRING, not counted as a record
    Varint(id);
    Str(s);
    return id;
  }
  void Varint(uint64_t v) {
    while (v >= 0x80) buf_.push_back(char((v & 0x7F) | 0x80)), v >>= 7;
    buf_.push_back(char(v));
  }
  void Svarint(int64_t v) { Varint((uint64_t(v) << 1) ^ uint64_t(v >> 63)); }
  void U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) buf_.push_back(char((v >> (8 * i)) & 0xFF));
  }
  void U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) buf_.push_back(char((v >> (8 * i)) & 0xFF));
  }
  void F64(double d) {
    uint64_t v;
    std::memcpy(&v, &d, 8);
    U64(v);
  }
  void Str(const std::string& s) {
    Varint(s.size());
    buf_.append(s);
  }

  std::string path_, tmp_;
  Level level_;
  std::FILE* file_ = nullptr;
  std::string buf_;
  uint64_t written_ = 0, records_ = 0;
  std::map<std::string, uint64_t> ids_;
  std::vector<std::string> table_;
  std::vector<Group> groups_;
  bool in_group_ = false;
  int64_t group_frame_ = -1;
  uint64_t group_start_ = 0, group_records_ = 0;
  uint32_t group_crc_ = 0;
};

}  // namespace dynref_trace
