// Typed landmark ids, per-landmark dynamic state and landmark lifecycle events (issue 12).
// The backbone has point landmarks; line and plane landmarks (seed 000) use the same id and
// event types, so a stage that keeps state per landmark (e.g. a dynamic probability by map
// point id) learns when its landmark is replaced by another or culled, and never goes stale.
#pragma once
#include <cstdint>
#include <string>

namespace dynref {

enum class LandmarkType { kPoint, kLine, kPlane };
const char* LandmarkTypeName(LandmarkType t);  // "point" | "line" | "plane"

struct LandmarkId {
  LandmarkType type = LandmarkType::kPoint;
  int64_t id = -1;
  bool operator<(const LandmarkId& o) const { return type != o.type ? type < o.type : id < o.id; }
  bool operator==(const LandmarkId& o) const { return type == o.type && id == o.id; }
};

// Dynamic state a method may keep on a landmark (the backbone never reads it): the probability
// that the landmark moves, when and by which stage it was last set. p < 0: never set.
struct LandmarkDynamicState {
  double p_dynamic = -1;
  int frame = -1;
  std::string stage;
};

struct LandmarkEvent {
  enum class Kind {
    kCreated,   // a new landmark (id)
    kReplaced,  // id was fused into by_id (ORB-SLAM2 MapPoint::Replace); id is bad from now on
    kCulled,    // id was set bad (too few observations, culling, keyframe removal)
  };
  Kind kind = Kind::kCreated;
  LandmarkId landmark;
  int64_t by_id = -1;  // kReplaced only
};
const char* LandmarkEventName(LandmarkEvent::Kind k);  // "created" | "replaced" | "culled"

class LandmarkObserver {
 public:
  virtual ~LandmarkObserver() = default;
  virtual void OnLandmarkEvent(const LandmarkEvent& event) = 0;
};

}  // namespace dynref
