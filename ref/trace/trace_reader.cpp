#include "trace/trace_reader.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstring>

#include "core/crc32c.h"
#include "core/format.h"
#include "trace/trace_format.h"

namespace dynref::trace {

const char* TraceProblemName(TraceProblem problem) {
  switch (problem) {
    case TraceProblem::kUnreadable: return "unreadable";
    case TraceProblem::kNotATrace: return "not a dynref trace";
    case TraceProblem::kSchemaVersion: return "other schema version";
    case TraceProblem::kTruncated: return "truncated";
    case TraceProblem::kCorrupt: return "corrupt";
  }
  return "unknown";
}

const char* RecordTypeName(RecordType type) {
  switch (type) {
    case RecordType::kFrame: return "frame";
    case RecordType::kPose: return "pose";
    case RecordType::kCount: return "count";
    case RecordType::kObservation: return "obs";
    case RecordType::kProbability: return "prob";
    case RecordType::kResidual: return "residual";
    case RecordType::kDecision: return "decision";
  }
  return "unknown";
}

EntityKind ParseEntityKind(const std::string& name) {
  for (int k = 0; k <= static_cast<int>(EntityKind::kFrame); ++k)
    if (name == EntityKindName(static_cast<EntityKind>(k))) return static_cast<EntityKind>(k);
  throw InputError("entity kind", "unknown entity kind '" + name + "'");
}

std::string ResolveTracePath(const std::string& run_or_file) {
  struct stat st {};
  if (::stat(run_or_file.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return run_or_file + "/trace.dtr";
  return run_or_file;
}

namespace {

// Bounds-checked decoder over one in-memory block.
class Cursor {
 public:
  Cursor(const std::string& path, const char* p, size_t n) : path_(path), p_(p), end_(p + n) {}
  bool AtEnd() const { return p_ >= end_; }
  size_t Pos(const char* begin) const { return static_cast<size_t>(p_ - begin); }
  uint32_t Fixed32() {
    Need(4);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<uint8_t>(p_[i])) << (8 * i);
    p_ += 4;
    return v;
  }
  uint8_t U8() {
    Need(1);
    return static_cast<uint8_t>(*p_++);
  }
  uint64_t Varint() {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const uint8_t b = U8();
      v |= static_cast<uint64_t>(b & 0x7F) << shift;
      if (!(b & 0x80)) return v;
    }
    Fail("varint longer than 10 bytes");
  }
  int64_t SVarint() {
    const uint64_t z = Varint();
    return static_cast<int64_t>((z >> 1) ^ (~(z & 1) + 1));
  }
  uint64_t Fixed64() {
    Need(8);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(static_cast<uint8_t>(p_[i])) << (8 * i);
    p_ += 8;
    return v;
  }
  double F64() {
    const uint64_t bits = Fixed64();
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
  }
  std::string Str() {
    const uint64_t n = Varint();
    Need(n);
    std::string s(p_, n);
    p_ += n;
    return s;
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw TraceError(path_, TraceProblem::kCorrupt, what);
  }

 private:
  void Need(uint64_t n) const {
    if (static_cast<uint64_t>(end_ - p_) < n) Fail("record runs past the end of its block");
  }
  const std::string& path_;
  const char* p_;
  const char* end_;
};

std::string ReadAt(FILE* f, const std::string& path, uint64_t offset, uint64_t size) {
  std::string buf(size, '\0');
  if (std::fseek(f, static_cast<long>(offset), SEEK_SET) != 0 ||
      std::fread(buf.data(), 1, size, f) != size)
    throw TraceError(path, TraceProblem::kTruncated, "cannot read " + std::to_string(size) +
                                                         " bytes at offset " + std::to_string(offset));
  return buf;
}

std::string Hex32(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%08x", v);
  return b;
}

uint32_t LoadU32(const char* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<uint8_t>(p[i])) << (8 * i);
  return v;
}

// A string-table reference (varint id) in a frame block.
const std::string& ReadStringRef(Cursor& c, const std::vector<std::string>& strings) {
  const uint64_t id = c.Varint();
  if (id >= strings.size()) c.Fail("string id " + std::to_string(id) + " not in the table");
  return strings[id];
}

EntityKind ReadEntityKind(Cursor& c) {
  const uint8_t kind = c.U8();
  if (kind > static_cast<uint8_t>(EntityKind::kFrame)) c.Fail("bad entity kind");
  return static_cast<EntityKind>(kind);
}

void ReadObservationBody(Cursor& c, int schema_version, Record* r) {
  r->type = RecordType::kObservation;
  r->feature_index = c.SVarint();
  r->map_point_id = c.SVarint();
  // Schema 3 adds the association the stages saw; before it, the final one is all there is.
  r->associated_map_point_id = schema_version >= 3 ? c.SVarint() : r->map_point_id;
  r->u = c.F64();
  r->v = c.F64();
  r->depth_m = c.F64();
  r->octave = c.SVarint();
  r->descriptor_hash = c.Fixed64();
}

void ReadProbabilityBody(Cursor& c, const std::vector<std::string>& strings, Record* r) {
  r->type = RecordType::kProbability;
  r->stage = ReadStringRef(c, strings);
  r->kind = ReadEntityKind(c);
  r->entity = c.Str();
  const uint64_t n = c.Varint();
  for (uint64_t i = 0; i < n; ++i) {
    NamedValue nv;
    nv.name = ReadStringRef(c, strings);
    nv.value = c.F64();
    r->inputs.push_back(std::move(nv));
  }
  r->before = c.F64();
  r->after = c.F64();
}

void ReadResidualBody(Cursor& c, const std::vector<std::string>& strings, Record* r) {
  r->type = RecordType::kResidual;
  r->stage = ReadStringRef(c, strings);
  r->residual_kind = ReadStringRef(c, strings);
  r->entity = c.Str();
  const uint64_t ns = c.Varint();
  for (uint64_t i = 0; i < ns; ++i) r->residual_start.push_back(c.F64());
  const uint64_t ne = c.Varint();
  for (uint64_t i = 0; i < ne; ++i) r->residual_end.push_back(c.F64());
  r->information = c.F64();
  r->weight = c.F64();
  r->robust_loss = c.F64();
  r->chi2 = c.F64();
  r->inlier = c.U8() != 0;
}

// The body of a record with the given tag (all but string definitions).
void ReadRecordBody(uint8_t tag, Cursor& c, const std::vector<std::string>& strings, int schema_version,
                    int64_t frame, Record* r) {
  switch (tag) {
    case format::kTagFrame:
      r->type = RecordType::kFrame;
      if (c.SVarint() != frame) c.Fail("frame record disagrees with the frame index");
      r->timestamp = c.F64();
      break;
    case format::kTagPose:
      r->type = RecordType::kPose;
      r->name = ReadStringRef(c, strings);
      for (double& d : r->T_wc) d = c.F64();
      break;
    case format::kTagCount:
      r->type = RecordType::kCount;
      r->stage = ReadStringRef(c, strings);
      r->name = ReadStringRef(c, strings);
      r->value = c.SVarint();
      break;
    case format::kTagObs:
      ReadObservationBody(c, schema_version, r);
      break;
    case format::kTagProb:
      ReadProbabilityBody(c, strings, r);
      break;
    case format::kTagResidual:
      ReadResidualBody(c, strings, r);
      break;
    case format::kTagDecision:
      r->type = RecordType::kDecision;
      r->stage = ReadStringRef(c, strings);
      r->kind = ReadEntityKind(c);
      r->entity = c.Str();
      r->kept = c.U8() != 0;
      r->reason = ReadStringRef(c, strings);
      break;
    default:
      c.Fail("unknown record tag " + std::to_string(tag));
  }
}

}  // namespace

TraceReader::TraceReader(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) throw TraceError(path, TraceProblem::kUnreadable, "cannot open file");
  std::fseek(file_, 0, SEEK_END);
  const long size = std::ftell(file_);
  if (size < format::kPreambleSize)
    throw TraceError(path, TraceProblem::kTruncated, "file shorter than the 16-byte preamble");
  const std::string pre = ReadAt(file_, path, 0, format::kPreambleSize);
  if (std::memcmp(pre.data(), format::kMagic, 8) != 0)
    throw TraceError(path, TraceProblem::kNotATrace, "missing DYNTRACE magic");
  const uint32_t version = LoadU32(pre.data() + 8);
  if (version < static_cast<uint32_t>(kOldestReadableSchema) ||
      version > static_cast<uint32_t>(kSchemaVersion))
    throw TraceError(path, TraceProblem::kSchemaVersion,
                     "trace has schema version " + std::to_string(version) +
                         ", this dynref reads schema versions " +
                         std::to_string(kOldestReadableSchema) + " to " +
                         std::to_string(kSchemaVersion));
  schema_version_ = static_cast<int>(version);
  const bool checksummed = schema_version_ >= 2;
  const uint8_t level = static_cast<uint8_t>(pre[12]);
  if (level > 2) throw TraceError(path, TraceProblem::kCorrupt, "bad level byte");
  level_ = static_cast<Level>(level);
  if (size < format::kPreambleSize + format::kTrailerSize)
    throw TraceError(path, TraceProblem::kTruncated, "no footer (file ends before the trailer)");
  const std::string trailer = ReadAt(file_, path, size - format::kTrailerSize, format::kTrailerSize);
  if (std::memcmp(trailer.data() + 8, format::kEndMagic, 8) != 0)
    throw TraceError(path, TraceProblem::kTruncated,
                     "no DYNTREND trailer: the writer did not finish (crash or cut file)");
  {
    Cursor t(path, trailer.data(), 8);
    footer_offset_ = t.Fixed64();
  }
  if (footer_offset_ < format::kPreambleSize ||
      footer_offset_ >= static_cast<uint64_t>(size - format::kTrailerSize))
    throw TraceError(path, TraceProblem::kCorrupt, "footer offset out of range");
  // Header (right after the preamble); read a bounded prefix of the body.
  {
    const uint64_t n = footer_offset_ - format::kPreambleSize;
    const std::string head = ReadAt(file_, path, format::kPreambleSize, n);
    Cursor c(path, head.data(), head.size());
    const uint64_t count = c.Varint();
    for (uint64_t i = 0; i < count; ++i) {
      std::string k = c.Str();
      header_.emplace_back(std::move(k), c.Str());
    }
    body_offset_ = format::kPreambleSize + c.Pos(head.data());
    if (checksummed) {
      const uint32_t computed = Crc32cExtend(Crc32c(pre), head.data(), c.Pos(head.data()));
      const uint32_t stored = c.Fixed32();
      if (stored != computed)
        throw TraceError(path, TraceProblem::kCorrupt,
                         "header checksum mismatch (CRC-32C stored " + Hex32(stored) +
                             ", computed " + Hex32(computed) + ")");
      body_offset_ += 4;
    }
  }
  const uint64_t footer_size = static_cast<uint64_t>(size - format::kTrailerSize) - footer_offset_;
  std::string footer = ReadAt(file_, path, footer_offset_, footer_size);
  if (checksummed) {
    if (footer.size() < 5) throw TraceError(path, TraceProblem::kCorrupt, "footer too short");
    const uint32_t stored = LoadU32(footer.data() + footer.size() - 4);
    footer.resize(footer.size() - 4);
    const uint32_t computed = Crc32c(footer);
    if (stored != computed)
      throw TraceError(path, TraceProblem::kCorrupt,
                       "footer checksum mismatch (CRC-32C stored " + Hex32(stored) +
                           ", computed " + Hex32(computed) + ")");
  }
  Cursor c(path, footer.data(), footer.size());
  if (c.U8() != format::kTagFooter) c.Fail("footer does not start with tag 0x7F");
  record_count_ = c.Varint();
  end_state_ = c.Str();
  const uint64_t groups = c.Varint();
  for (uint64_t i = 0; i < groups; ++i) {
    Group g;
    g.frame = c.SVarint();
    g.offset = c.Varint();
    g.records = c.Varint();
    if (checksummed) g.crc = c.Fixed32();
    if (g.offset < format::kPreambleSize || g.offset > footer_offset_ ||
        (!groups_.empty() && g.offset < groups_.back().offset))
      c.Fail("frame index offset out of order or range");
    groups_.push_back(g);
  }
  const uint64_t nstrings = c.Varint();
  for (uint64_t i = 0; i < nstrings; ++i) strings_.push_back(c.Str());
  if (!c.AtEnd()) c.Fail("extra bytes after the string table");
  // Schema 2: the groups tile the body exactly, so every body byte is under a checksum.
  if (checksummed && (groups_.empty() ? footer_offset_ != body_offset_
                                      : groups_.front().offset != body_offset_))
    c.Fail("frame groups do not start where the body starts");
}

TraceReader::~TraceReader() {
  if (file_) std::fclose(file_);
}

std::string TraceReader::HeaderValue(const std::string& key) const {
  for (const auto& [k, v] : header_)
    if (k == key) return v;
  return "";
}

std::vector<Record> TraceReader::ReadGroup(size_t gi) {
  const Group& g = groups_.at(gi);
  const uint64_t end = gi + 1 < groups_.size() ? groups_[gi + 1].offset : footer_offset_;
  const std::string block = ReadAt(file_, path_, g.offset, end - g.offset);
  if (schema_version_ >= 2) {
    const uint32_t computed = Crc32c(block);
    if (computed != g.crc)
      throw TraceError(path_, TraceProblem::kCorrupt,
                       "at frame " + std::to_string(g.frame) + ": block checksum mismatch (CRC-32C stored " +
                           Hex32(g.crc) + ", computed " + Hex32(computed) + ")");
  }
  Cursor c(path_, block.data(), block.size());
  std::vector<Record> out;
  out.reserve(std::min<uint64_t>(g.records, block.size()));  // a record has >= 1 byte
  while (!c.AtEnd()) {
    const uint8_t tag = c.U8();
    if (tag == format::kTagString) {
      const uint64_t id = c.Varint();
      const std::string s = c.Str();
      if (id >= strings_.size() || strings_[id] != s) c.Fail("string definition disagrees with table");
      continue;
    }
    Record r;
    r.frame = g.frame;
    ReadRecordBody(tag, c, strings_, schema_version_, g.frame, &r);
    out.push_back(std::move(r));
  }
  if (out.size() != g.records)
    throw TraceError(path_, TraceProblem::kCorrupt,
                     "frame " + std::to_string(g.frame) + " has " + std::to_string(out.size()) +
                         " records, index says " + std::to_string(g.records));
  return out;
}

}  // namespace dynref::trace
