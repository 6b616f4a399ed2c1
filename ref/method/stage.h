// A method is a list of stages (and map modules, map_module.h) named in its config, each run at
// one hook (hooks.h). A stage reads the frame, the previous frame, the map and the camera, and
// changes the frame only through its FrameEdit (frame_edit.h). Everything a stage writes into
// the run folder is written in Finish (run_end.h), never in a destructor, so that a failed
// write reaches run.json.
#pragma once
#include <string>

#include "io/camera.h"
#include "map/frame.h"
#include "map/landmark.h"
#include "map/map.h"
#include "method/frame_edit.h"
#include "method/hooks.h"
#include "method/run_end.h"
#include "trace/trace_writer.h"

namespace dynref {

struct StageContext {
  FrameEdit& frame;                 // the current frame: frame.view() to read (T_cw valid when has_pose)
  const Frame* previous;            // previous frame (nullptr for the first), with its pose
  const KeyFrame* reference_kf;     // tracking reference keyframe (nullptr before init)
  const Map& map;                   // keyframes (with rgb, depth_m, keys) and map points
  const Camera& camera;
  trace::TraceWriter& trace;
  bool initialised = false;         // map initialised (a pose exists for previous frames)
  bool lost = false;                // tracking state before this frame
  // Only at kOnKeyFrameCreated / kOnMapUpdate: the new keyframe, and the handle that edits the
  // keyframe's own copy of the frame (what local mapping and local BA use).
  const KeyFrame* new_keyframe = nullptr;
  FrameEdit* new_keyframe_edit = nullptr;
  // The run's --threads: a stage may split work over this many threads when the result stays
  // bit-identical (e.g. Lucas-Kanade over slices of points).
  int threads = 1;
};

class Stage {
 public:
  virtual ~Stage() = default;
  virtual std::string name() const = 0;
  virtual Hook hook() const = 0;
  virtual void Run(StageContext& ctx) = 0;
  // A landmark was created, replaced or culled (map/landmark.h); default: ignored.
  virtual void OnLandmarkEvent(const LandmarkEvent&) {}
  // End of run: write outputs into end.out_dir and report them (default: none). Throwing ends
  // the run with an error in run.json.
  virtual void Finish(RunEnd&) {}
};

}  // namespace dynref
