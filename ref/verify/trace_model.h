// The whole trace in memory, indexed for `dynref trace verify` (ref/verify/README.md): every
// frame's records in file order, the resolved config and camera of the header, and look-ups the
// per-stage verifiers share (an observation by frame and index, the records of one entity).
// Nothing here knows a stage: the verifiers read the trace as any other implementation would.
#pragma once
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "trace/trace_reader.h"

namespace dynref::verify {

struct FrameRecords {
  int64_t frame = -1;
  std::vector<trace::Record> records;  // file order
};

// Pinhole camera from the header key "camera_json" (writers add it since schema 3).
struct CameraModel {
  bool present = false;
  double fx = 0, fy = 0, cx = 0, cy = 0, bf = 0, th_depth = 0;
  int width = 0, height = 0;
};

// Where a record sits: frames()[frame_pos].records[index].
struct RecordRef {
  size_t frame_pos = 0;
  size_t index = 0;
};

class TraceModel {
 public:
  explicit TraceModel(trace::TraceReader& reader);

  const std::string& path() const { return path_; }
  int schema_version() const { return schema_version_; }
  const std::vector<FrameRecords>& frames() const { return frames_; }
  const trace::Record& At(RecordRef r) const { return frames_[r.frame_pos].records[r.index]; }
  const nlohmann::json& config() const { return config_; }
  const CameraModel& camera() const { return camera_; }
  std::string HeaderValue(const std::string& key) const;

  // A stage's parameter value as text ("" and false when the stage or key is absent).
  bool StageParam(const std::string& stage, const std::string& key, std::string* value) const;
  // The same as a number (nullopt when absent or not a number; "true"/"false" read as 1/0).
  std::optional<double> StageNumber(const std::string& stage, const std::string& key) const;
  std::optional<double> BackboneNumber(const std::string& key) const;
  bool HasStage(const std::string& stage) const;
  // A stage's list parameter of COCO classes (names with spaces or '_', or ids) as class ids
  // (io/coco_classes.h: the detection format's table); empty when absent.
  std::set<int> StageClassIds(const std::string& stage, const std::string& key) const;

  // Position of frame `frame` in frames() (the last group of that number), nullopt if absent.
  std::optional<size_t> FramePos(int64_t frame) const;
  // The OBS record of feature `index` in frame group `frame_pos` (nullptr if none).
  const trace::Record* Obs(size_t frame_pos, int64_t index) const;
  // Every record (any frame) whose entity is `id`, in processing order.
  const std::vector<RecordRef>& EntityRecords(const std::string& id) const;

 private:
  std::string path_;
  int schema_version_ = 0;
  std::vector<std::pair<std::string, std::string>> header_;
  std::vector<FrameRecords> frames_;
  nlohmann::json config_;
  CameraModel camera_;
  std::map<int64_t, size_t> frame_pos_;
  std::vector<std::map<int64_t, size_t>> obs_;            // per frame_pos: feature index -> record index
  std::map<std::string, std::vector<RecordRef>> entity_;  // entity id -> records
};

class Check;

// Input `name` of a PROB record (nullopt if the record has no such input).
std::optional<double> Input(const trace::Record& r, const std::string& name);

// The confidence threshold a mask stage applied to the instance of record `r` (issue 39): the
// config's `min_confidence` (the paper's number), or, when the stage mapped it to its detection
// source's scale (`threshold_scale: detector` with a calibrated source such as NanoDet), the
// `applied_min_confidence` input the stage recorded. A recorded value under `threshold_scale: raw`
// or outside [0, 1] is a mismatch; the source's calibration itself is the detector's, not a
// trace record (reports/real_people.md), so it is taken as recorded.
double AppliedMinConfidence(const TraceModel& t, const trace::Record& r, const std::string& stage, Check& c);
// Parses "<prefix><a>.<b>" (e.g. "f12.3") into a, b; false otherwise.
bool ParseDottedId(const std::string& id, const std::string& prefix, int64_t* a, int64_t* b);
// Parses "<prefix><n>" (e.g. "mp17") into n; false otherwise.
bool ParseNumberId(const std::string& id, const std::string& prefix, int64_t* n);

}  // namespace dynref::verify
