// Trace writer: the API every stage logs through (schema documented in ref/trace/README.md).
// CONTRACT shared by the backbone, every method and the validator; change it only together.
//
// Records are keyed, never position-based. Key of a record:
//   (frame, record type, stage or optimiser call id, entity kind, entity id, field)
// Canonical entity ids (strings):
//   feature observation "f<frame>.<index>"   map point "mp<id>"        keyframe "kf<id>"
//   instance mask       "i<frame>.<inst>"    line sample "l<frame>.<index>"
//   plane               "pl<frame>.<index>"  pixel region "r<frame>.<index>"
// Residual observation ids: "<entity id>@<kf or frame>", e.g. "mp17@f42" or "mp17@kf3".
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/se3.h"

namespace dynref::trace {

constexpr int kSchemaVersion = 3;          // what the writer writes (3: OBS associated_map_point_id)
constexpr int kOldestReadableSchema = 1;   // readers still accept schema 1 (no checksums)

enum class Level : uint8_t { kOff = 0, kFrames = 1, kFull = 2 };
Level ParseLevel(const std::string& text);  // "off" | "frames" | "full"; InputError otherwise
const char* LevelName(Level level);

enum class EntityKind : uint8_t {
  kFeature = 0,      // a keypoint observation in one frame
  kMapPoint = 1,
  kKeyFrame = 2,
  kLineSample = 3,
  kPlane = 4,
  kInstanceMask = 5,
  kPixelRegion = 6,
  kFrame = 7,
};
const char* EntityKindName(EntityKind kind);
// Stage of the backbone's line / plane geometry records (structure room, issue 13): PROB records
// whose before/after (0) are not probabilities, only carriers of the geometry inputs. Readers
// that draw or count probabilities skip them.
constexpr const char* kGeometryStage = "structure";

struct NamedValue {
  std::string name;
  double value = 0;
};

struct RunHeader {
  std::string dynref_version;
  std::string dynref_commit;
  std::string method;
  std::string config_json;      // fully resolved configuration (every parameter, with sources)
  std::string sequence_path;
  std::vector<std::pair<std::string, std::string>> input_hashes;  // (file, sha256), sorted by file
  std::string detector_source;  // e.g. "none", "synthetic:yolo-like", "nanodet sha256:..."
  std::string detections_dir;   // detections folder used (empty if none); read by overlays
  // Further keys written after the fixed ones, e.g. "camera_json" (the pinhole camera the
  // verifier back-projects with); readers ignore keys they do not know.
  std::vector<std::pair<std::string, std::string>> extra;
};

class TraceWriter {
 public:
  // Opens path (usually RUN/trace.dtr) for writing through a temp file; Close() renames it.
  // With Level::kOff no file is created and every call is a cheap no-op.
  TraceWriter(const std::string& path, Level level, const RunHeader& header);
  ~TraceWriter();  // without Close(): temp file removed, nothing appears under `path`
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  Level level() const { return level_; }
  // Records from several threads (--variant concurrent: the local-mapping thread's residuals
  // while tracking goes on): each call then takes a mutex, so records never interleave; which
  // frame group a record lands in depends on timing. Off by default (the oracle pays nothing).
  void SetThreadSafe(bool on) { thread_safe_ = on; }
  bool frames_enabled() const { return level_ >= Level::kFrames; }
  bool full_enabled() const { return level_ >= Level::kFull; }

  // ---- frame level (Level::kFrames and above) ----
  // Starts frame `frame`; every following record belongs to it until the next BeginFrame.
  void BeginFrame(int frame, double timestamp);
  // which: "initial" (before final optimisation), "final" (after).
  void FramePose(const std::string& which, const SE3& T_wc);
  // Per-stage counters, e.g. ("extract", "keypoints", 1000), ("sgdo.epipolar", "rejected", 37).
  void FrameCount(const std::string& stage, const std::string& name, int64_t value);

  // ---- full level only (no-ops below Level::kFull) ----
  // map_point_id: the final inlier association (-1 none); associated_map_point_id: the map point
  // the feature was associated with when the stages saw it, kept when an exclusion or the final
  // optimisation (outlier) dropped it (-1: never associated; README "OBS").
  void Observation(int64_t feature_index, int64_t map_point_id, int64_t associated_map_point_id,
                   double u, double v, double depth_m /* 0 if none */, int octave,
                   uint64_t descriptor_hash);
  // Schema 2 form: associated_map_point_id = map_point_id.
  void Observation(int64_t feature_index, int64_t map_point_id /* -1 if unmatched */, double u,
                   double v, double depth_m /* 0 if none */, int octave, uint64_t descriptor_hash) {
    Observation(feature_index, map_point_id, map_point_id, u, v, depth_m, octave, descriptor_hash);
  }
  void ProbabilityUpdate(const std::string& stage, EntityKind kind, const std::string& entity_id,
                         const std::vector<NamedValue>& inputs, double before, double after);
  // One residual of one optimiser call. call_id e.g. "track.pose#2" (per-frame counter) or
  // "localba#17" (global counter). residual_kind e.g. "rgbd3", "mono2".
  void Residual(const std::string& call_id, const std::string& residual_kind,
                const std::string& observation_id, const std::vector<double>& residual_start,
                const std::vector<double>& residual_end, double information, double weight,
                double robust_loss, double chi2, bool inlier);
  void Decision(const std::string& stage, EntityKind kind, const std::string& entity_id, bool kept,
                const std::string& reason);

  // Writes the footer (record count, end state such as "complete", "lost-at-end", "error: ...")
  // and atomically renames the temp file to `path`.
  void Close(const std::string& end_state);

 private:
  std::unique_lock<std::mutex> Guard();  // locked when thread-safe, else empty
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Level level_;
  bool thread_safe_ = false;
  std::mutex mutex_;
};

}  // namespace dynref::trace
