// Streaming reader of trace.dtr (schema in ref/trace/README.md) and the canonical "flat" view of
// a record (key + named fields) shared by dump, diff and the feature history.
// Only the footer (frame index + string table) is held in memory; records are read one frame
// group at a time.
#pragma once
#include <array>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"
#include "trace/trace_writer.h"

namespace dynref::trace {

// Why a trace cannot be used (all map to exit code 2).
enum class TraceProblem { kUnreadable, kNotATrace, kSchemaVersion, kTruncated, kCorrupt };
const char* TraceProblemName(TraceProblem problem);

class TraceError : public InputError {
 public:
  TraceError(const std::string& file, TraceProblem problem, const std::string& what)
      : InputError(file, std::string(TraceProblemName(problem)) +
                             (what.rfind("at frame ", 0) == 0 ? " " : ": ") + what),
        problem_(problem) {}
  TraceProblem problem() const { return problem_; }

 private:
  TraceProblem problem_;
};

enum class RecordType : uint8_t {
  kFrame = 2, kPose = 3, kCount = 4, kObservation = 5, kProbability = 6, kResidual = 7,
  kDecision = 8,
};
const char* RecordTypeName(RecordType type);  // frame pose count obs prob residual decision
EntityKind ParseEntityKind(const std::string& name);  // InputError if unknown

// One decoded record; which members are meaningful depends on `type`.
struct Record {
  RecordType type = RecordType::kFrame;
  int64_t frame = -1;               // frame group (-1: before the first BeginFrame)
  double timestamp = 0;             // kFrame
  std::string name;                 // kPose: "initial"/"final"; kCount: counter name
  std::array<double, 12> T_wc{};    // kPose: rows 0..2 of the 4x4 matrix, row-major
  std::string stage;                // kCount/kProbability/kDecision: stage; kResidual: call id
  int64_t value = 0;                // kCount
  int64_t feature_index = 0, map_point_id = -1, octave = 0;  // kObservation
  // kObservation: map point when the stages saw the feature (schema 3; schema 1/2: map_point_id)
  int64_t associated_map_point_id = -1;
  double u = 0, v = 0, depth_m = 0;                          // kObservation
  uint64_t descriptor_hash = 0;                              // kObservation
  EntityKind kind = EntityKind::kFeature;  // kProbability/kDecision
  std::string entity;               // kProbability/kDecision: entity id; kResidual: observation id
  std::vector<NamedValue> inputs;   // kProbability
  double before = 0, after = 0;     // kProbability
  std::string residual_kind;        // kResidual
  std::vector<double> residual_start, residual_end;
  double information = 0, weight = 0, robust_loss = 0, chi2 = 0;
  bool inlier = false;              // kResidual
  bool kept = false;                // kDecision
  std::string reason;               // kDecision
};

// Canonical key + fields of a record (README "Canonical view"). Exact fields carry text,
// float fields a double.
struct FlatField {
  std::string name;
  bool exact = false;
  double number = 0;
  std::string text;
};
struct FlatRecord {
  int64_t frame = -1;
  std::string type, stage, kind, entity;
  int occurrence = 0;  // index among records of the same (frame,type,stage,kind,entity), file order
  std::vector<FlatField> fields;
  std::string Key() const;  // "type|stage|kind|entity|occurrence" (frame not included)
};
FlatRecord Flatten(const Record& record);
// Flattens one frame group, assigning occurrences.
std::vector<FlatRecord> FlattenGroup(const std::vector<Record>& records);

class TraceReader {
 public:
  struct Group {
    int64_t frame;
    uint64_t offset;
    uint64_t records;
    uint32_t crc = 0;  // schema 2: CRC-32C of the group's bytes
  };
  // path: a trace file (schema 1, 2 or 3; schema >= 2 checksums are verified: the header and footer
  // here, each frame block in ReadGroup). Throws TraceError naming the problem (missing, truncated, version, ...).
  explicit TraceReader(const std::string& path);
  ~TraceReader();
  TraceReader(const TraceReader&) = delete;
  TraceReader& operator=(const TraceReader&) = delete;

  const std::string& path() const { return path_; }
  Level level() const { return level_; }
  int schema_version() const { return schema_version_; }
  const std::vector<std::pair<std::string, std::string>>& header() const { return header_; }
  std::string HeaderValue(const std::string& key) const;  // "" if absent
  const std::string& end_state() const { return end_state_; }
  uint64_t record_count() const { return record_count_; }
  const std::vector<Group>& groups() const { return groups_; }  // file order
  // Records of group i in file order (TraceError kCorrupt "corrupt at frame N" on a bad block).
  std::vector<Record> ReadGroup(size_t i);

 private:
  std::string path_;
  FILE* file_ = nullptr;
  Level level_ = Level::kOff;
  std::vector<std::pair<std::string, std::string>> header_;
  std::string end_state_;
  int schema_version_ = 0;
  uint64_t record_count_ = 0, footer_offset_ = 0, body_offset_ = 0;
  std::vector<Group> groups_;
  std::vector<std::string> strings_;
};

// RUN argument: a run directory (containing trace.dtr) or a trace file.
std::string ResolveTracePath(const std::string& run_or_file);

}  // namespace dynref::trace
