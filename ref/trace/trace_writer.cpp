// Trace writer: compact binary log (layout in ref/trace/README.md). Per record cost is a few
// appends to an in-memory buffer that is flushed to the temp file in 1 MiB blocks; stage names,
// call ids, pose/count names and decision reasons are interned in a string table.
#include "trace/trace_writer.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "core/atomic_file.h"
#include "core/crc32c.h"
#include "core/error.h"
#include "trace/trace_format.h"

namespace dynref::trace {

Level ParseLevel(const std::string& text) {
  if (text == "off") return Level::kOff;
  if (text == "frames") return Level::kFrames;
  if (text == "full") return Level::kFull;
  throw InputError("--trace", "unknown trace level '" + text + "' (expected off|frames|full)");
}

const char* LevelName(Level level) {
  switch (level) {
    case Level::kOff: return "off";
    case Level::kFrames: return "frames";
    case Level::kFull: return "full";
  }
  return "unknown";
}

const char* EntityKindName(EntityKind kind) {
  switch (kind) {
    case EntityKind::kFeature: return "feature";
    case EntityKind::kMapPoint: return "map_point";
    case EntityKind::kKeyFrame: return "keyframe";
    case EntityKind::kLineSample: return "line_sample";
    case EntityKind::kPlane: return "plane";
    case EntityKind::kInstanceMask: return "instance_mask";
    case EntityKind::kPixelRegion: return "pixel_region";
    case EntityKind::kFrame: return "frame";
  }
  return "unknown";
}

namespace {
constexpr size_t kFlushBytes = size_t{1} << 20;
}  // namespace

struct TraceWriter::Impl {
  // Not in the anonymous namespace: a member's type there gives Impl internal linkage parts
  // (-Wsubobject-linkage in unity builds).
  struct FrameIndexEntry {
    int64_t frame;
    uint64_t offset;
    uint64_t records;
    uint32_t crc = 0;  // CRC-32C of the group's bytes [offset, next group's offset or footer)
  };
  std::string final_path, temp_path;
  FILE* file = nullptr;
  std::string buf;              // pending bytes
  uint64_t flushed = 0;         // bytes already written to the file
  uint64_t records = 0;         // body records excluding string definitions
  std::unordered_map<std::string, uint64_t> strings;
  std::vector<std::string> string_table;
  std::vector<FrameIndexEntry> index;
  std::vector<uint64_t> scratch;  // string ids of one record's input names
  uint64_t crc_pos = 0;          // bytes before this offset are folded into group_crc
  uint32_t group_crc = 0;        // running CRC-32C of the current frame group
  bool closed = false;

  uint64_t Offset() const { return flushed + buf.size(); }

  // Folds the pending bytes not yet checksummed into the current group's CRC.
  void FeedCrc() {
    const size_t from = static_cast<size_t>(crc_pos - flushed);
    group_crc = Crc32cExtend(group_crc, buf.data() + from, buf.size() - from);
    crc_pos = Offset();
  }
  // Closes the current group's checksum and starts a new group at the current offset.
  void StartGroup(int64_t frame) {
    FeedCrc();
    if (!index.empty()) index.back().crc = group_crc;
    group_crc = 0;
    index.push_back({frame, Offset(), 0});
  }
  // Bytes before the first BeginFrame (string definitions, records) form group -1, so every
  // body byte belongs to exactly one checksummed group.
  void EnsureGroup() {
    if (index.empty()) StartGroup(-1);
  }

  void Flush() {
    if (buf.empty()) return;
    FeedCrc();
    if (std::fwrite(buf.data(), 1, buf.size(), file) != buf.size())
      throw std::runtime_error("trace: write failed: " + temp_path);
    flushed += buf.size();
    buf.clear();
  }
  void MaybeFlush() {
    if (buf.size() >= kFlushBytes) Flush();
  }

  void U8(uint8_t v) { buf.push_back(static_cast<char>(v)); }
  void Fixed32(uint32_t v) {
    for (int i = 0; i < 4; ++i) U8(static_cast<uint8_t>((v >> (8 * i)) & 0xFF));
  }
  void Varint(uint64_t v) {
    while (v >= 0x80) {
      buf.push_back(static_cast<char>((v & 0x7F) | 0x80));
      v >>= 7;
    }
    buf.push_back(static_cast<char>(v));
  }
  void SVarint(int64_t v) {  // zigzag
    Varint((static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63));
  }
  void Fixed64(uint64_t v) {
    char b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<char>((v >> (8 * i)) & 0xFF);
    buf.append(b, 8);
  }
  void F64(double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, 8);
    Fixed64(bits);
  }
  void Str(const std::string& s) {
    Varint(s.size());
    buf.append(s);
  }
  // Interned string id; defines the string (a kTagString record) when it is new. Must be
  // called BEFORE the record that uses it starts, so definitions never split a record.
  uint64_t Intern(const std::string& s) {
    auto it = strings.find(s);
    if (it != strings.end()) return it->second;
    EnsureGroup();
    const uint64_t id = string_table.size();
    strings.emplace(s, id);
    string_table.push_back(s);
    U8(format::kTagString);
    Varint(id);
    Str(s);
    return id;
  }
  // Every non-string record goes through here: counts it for the current frame group.
  void StartRecord() {
    EnsureGroup();
    ++index.back().records;
    ++records;
  }
};

TraceWriter::TraceWriter(const std::string& path, Level level, const RunHeader& header)
    : level_(level) {
  if (level_ == Level::kOff) return;
  impl_ = std::make_unique<Impl>();
  impl_->final_path = path;
  impl_->temp_path = TempPathFor(path);
  impl_->file = std::fopen(impl_->temp_path.c_str(), "wb");
  if (!impl_->file) throw InputError(path, "cannot open trace for writing");
  impl_->buf.reserve(kFlushBytes + 4096);
  Impl& w = *impl_;
  w.buf.append(format::kMagic, 8);
  w.Fixed32(kSchemaVersion);
  w.U8(static_cast<uint8_t>(level_));
  w.U8(0), w.U8(0), w.U8(0);
  // Header: key/value list (README "Header"); unknown keys are ignored by readers.
  std::vector<std::pair<std::string, std::string>> kv = {
      {"dynref_version", header.dynref_version}, {"dynref_commit", header.dynref_commit},
      {"method", header.method},                 {"config_json", header.config_json},
      {"sequence_path", header.sequence_path},   {"detector_source", header.detector_source},
      {"detections_dir", header.detections_dir}};
  for (const auto& [file, hash] : header.input_hashes) kv.push_back({"input_sha256:" + file, hash});
  for (const auto& [key, value] : header.extra) kv.push_back({key, value});
  w.Varint(kv.size());
  for (const auto& [k, v] : kv) {
    w.Str(k);
    w.Str(v);
  }
  w.Fixed32(Crc32c(w.buf));  // schema 2: CRC-32C over preamble + header
  w.crc_pos = w.Offset();    // the body starts here
}

TraceWriter::~TraceWriter() {
  if (!impl_ || impl_->closed) return;
  if (impl_->file) std::fclose(impl_->file);
  std::remove(impl_->temp_path.c_str());
}

std::unique_lock<std::mutex> TraceWriter::Guard() {
  return thread_safe_ ? std::unique_lock<std::mutex>(mutex_) : std::unique_lock<std::mutex>();
}

void TraceWriter::BeginFrame(int frame, double timestamp) {
  if (!frames_enabled()) return;
  const std::unique_lock<std::mutex> guard = Guard();
  Impl& w = *impl_;
  w.StartGroup(frame);
  w.StartRecord();
  w.U8(format::kTagFrame);
  w.SVarint(frame);
  w.F64(timestamp);
  w.MaybeFlush();
}

void TraceWriter::FramePose(const std::string& which, const SE3& T_wc) {
  if (!frames_enabled()) return;
  const std::unique_lock<std::mutex> guard = Guard();
  Impl& w = *impl_;
  const uint64_t which_id = w.Intern(which);
  w.StartRecord();
  w.U8(format::kTagPose);
  w.Varint(which_id);
  const Eigen::Matrix4d& m = T_wc.matrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w.F64(m(r, c));
  w.MaybeFlush();
}

void TraceWriter::FrameCount(const std::string& stage, const std::string& name, int64_t value) {
  if (!frames_enabled()) return;
  const std::unique_lock<std::mutex> guard = Guard();
  Impl& w = *impl_;
  const uint64_t stage_id = w.Intern(stage), name_id = w.Intern(name);
  w.StartRecord();
  w.U8(format::kTagCount);
  w.Varint(stage_id);
  w.Varint(name_id);
  w.SVarint(value);
  w.MaybeFlush();
}

void TraceWriter::Observation(int64_t feature_index, int64_t map_point_id,
                              int64_t associated_map_point_id, double u, double v, double depth_m,
                              int octave, uint64_t descriptor_hash) {
  if (!full_enabled()) return;
  const std::unique_lock<std::mutex> guard = Guard();
  Impl& w = *impl_;
  w.StartRecord();
  w.U8(format::kTagObs);
  w.SVarint(feature_index);
  w.SVarint(map_point_id);
  w.SVarint(associated_map_point_id);  // schema 3
  w.F64(u);
  w.F64(v);
  w.F64(depth_m);
  w.SVarint(octave);
  w.Fixed64(descriptor_hash);
  w.MaybeFlush();
}

void TraceWriter::ProbabilityUpdate(const std::string& stage, EntityKind kind,
                                    const std::string& entity_id,
                                    const std::vector<NamedValue>& inputs, double before,
                                    double after) {
  if (!full_enabled()) return;
  const std::unique_lock<std::mutex> guard = Guard();
  Impl& w = *impl_;
  const uint64_t stage_id = w.Intern(stage);
  w.scratch.clear();
  for (const NamedValue& nv : inputs) w.scratch.push_back(w.Intern(nv.name));
  w.StartRecord();
  w.U8(format::kTagProb);
  w.Varint(stage_id);
  w.U8(static_cast<uint8_t>(kind));
  w.Str(entity_id);
  w.Varint(inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) {
    w.Varint(w.scratch[i]);
    w.F64(inputs[i].value);
  }
  w.F64(before);
  w.F64(after);
  w.MaybeFlush();
}

void TraceWriter::Residual(const std::string& call_id, const std::string& residual_kind,
                           const std::string& observation_id,
                           const std::vector<double>& residual_start,
                           const std::vector<double>& residual_end, double information,
                           double weight, double robust_loss, double chi2, bool inlier) {
  if (!full_enabled()) return;
  const std::unique_lock<std::mutex> guard = Guard();
  Impl& w = *impl_;
  const uint64_t call_ref = w.Intern(call_id), kind_ref = w.Intern(residual_kind);
  w.StartRecord();
  w.U8(format::kTagResidual);
  w.Varint(call_ref);
  w.Varint(kind_ref);
  w.Str(observation_id);
  w.Varint(residual_start.size());
  for (double d : residual_start) w.F64(d);
  w.Varint(residual_end.size());
  for (double d : residual_end) w.F64(d);
  w.F64(information);
  w.F64(weight);
  w.F64(robust_loss);
  w.F64(chi2);
  w.U8(inlier ? 1 : 0);
  w.MaybeFlush();
}

void TraceWriter::Decision(const std::string& stage, EntityKind kind, const std::string& entity_id,
                           bool kept, const std::string& reason) {
  if (!full_enabled()) return;
  const std::unique_lock<std::mutex> guard = Guard();
  Impl& w = *impl_;
  const uint64_t stage_id = w.Intern(stage), reason_id = w.Intern(reason);
  w.StartRecord();
  w.U8(format::kTagDecision);
  w.Varint(stage_id);
  w.U8(static_cast<uint8_t>(kind));
  w.Str(entity_id);
  w.U8(kept ? 1 : 0);
  w.Varint(reason_id);
  w.MaybeFlush();
}

void TraceWriter::Close(const std::string& end_state) {
  const std::unique_lock<std::mutex> guard = Guard();
  if (!impl_ || impl_->closed) return;
  Impl& w = *impl_;
  w.FeedCrc();
  if (!w.index.empty()) w.index.back().crc = w.group_crc;
  const uint64_t footer_offset = w.Offset();
  w.U8(format::kTagFooter);
  w.Varint(w.records);
  w.Str(end_state);
  w.Varint(w.index.size());
  for (const Impl::FrameIndexEntry& e : w.index) {
    w.SVarint(e.frame);
    w.Varint(e.offset);
    w.Varint(e.records);
    w.Fixed32(e.crc);
  }
  w.Varint(w.string_table.size());
  for (const std::string& s : w.string_table) w.Str(s);
  const size_t footer_in_buf = static_cast<size_t>(footer_offset - w.flushed);
  w.Fixed32(Crc32c(w.buf.data() + footer_in_buf, w.buf.size() - footer_in_buf));
  w.Fixed64(footer_offset);
  w.buf.append(format::kEndMagic, 8);
  w.Flush();
  const bool ok = std::fflush(w.file) == 0;
  const bool closed_ok = std::fclose(w.file) == 0;
  w.file = nullptr;
  w.closed = true;
  if (!ok || !closed_ok) {
    std::remove(w.temp_path.c_str());
    throw std::runtime_error("trace: write failed: " + w.temp_path);
  }
  AtomicRename(w.temp_path, w.final_path);
}

}  // namespace dynref::trace
