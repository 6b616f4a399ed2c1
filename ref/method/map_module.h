// A map module builds a map beside the backbone's sparse one (SGDO's dense static cloud, seed
// 002's semantic cloud / octree / grid): it sees every keyframe when it is created, again after
// local mapping has refined and culled the map, and writes its files at the end of the run.
// Named in a config's `stages:` list like a stage; created per run by the Session.
#pragma once
#include <string>

#include "io/camera.h"
#include "map/frame.h"
#include "map/landmark.h"
#include "map/map.h"
#include "method/run_end.h"
#include "trace/trace_writer.h"

namespace dynref {

struct MapModuleContext {
  const Frame& frame;          // the frame that became the keyframe (after every stage's edits)
  const KeyFrame& keyframe;    // the new keyframe (T_cw as created / after local BA)
  const Map& map;              // the whole map (final keyframe poses are read at Finish time)
  const Camera& camera;
  trace::TraceWriter& trace;
  int threads = 1;             // the run's --threads (a module may split work that stays bit-identical)
};

class MapModule {
 public:
  virtual ~MapModule() = default;
  virtual std::string name() const = 0;
  // A keyframe was created (after the kOnKeyFrameCreated stages, before local mapping).
  virtual void OnKeyFrame(const MapModuleContext& ctx) = 0;
  // Local mapping processed that keyframe (new points, BA, culling); default: nothing.
  virtual void OnMapUpdate(const MapModuleContext&) {}
  virtual void OnLandmarkEvent(const LandmarkEvent&) {}
  // End of run: `map` holds the final keyframe poses. Write files into end.out_dir, report each
  // with end.AddOutput; throw to report a failed write (the run then ends in error).
  virtual void Finish(const Map& map, RunEnd& end) = 0;
};

}  // namespace dynref
