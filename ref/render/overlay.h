// Off-screen overlays of a finished run (`dynref overlay`, `dynref run --overlays`): the RGB
// frame with every traced feature coloured by dynamic probability (viridis, legend), marker
// shape for the decision (kept / rejected / undecided), detector instance outlines + boxes +
// class + confidence, traced line samples and plane / pixel regions, frame index and per-stage
// counts, a marked border on a frame whose keyframe closed a loop; optionally ground-truth
// dynamic labels as rings (synthetic sequences, SEQ/gt/).
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "io/mask_format.h"
#include "io/mask_layers.h"
#include "render/canvas.h"
#include "trace/trace_reader.h"

namespace dynref::render {

// Where a run's inputs are: RUN/run.json ("sequence", "detections", optional "camera"), falling
// back to the trace header (sequence_path, detections_dir) when RUN is a trace file.
struct RunInfo {
  std::string trace_path, sequence, detections, camera;
};
RunInfo ReadRunInfo(const std::string& run_or_trace);

struct OverlayFeature {
  int64_t index = 0, map_point_id = -1;
  double u = 0, v = 0;
  bool has_prob = false;
  double prob = 0;     // last ProbabilityUpdate of f<frame>.<index>, else of mp<id> so far
  int decision = -1;   // last Decision in the frame on the feature (else its map point): 1 kept, 0 rejected
};
// Line samples (kLineSample: inputs x0,y0,x1,y1) and regions (kPlane / kPixelRegion: inputs
// x_min,y_min,x_max,y_max) as documented in ref/trace/README.md "Geometry inputs".
struct OverlayShape {
  trace::EntityKind kind = trace::EntityKind::kLineSample;
  std::string entity;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool has_prob = false;
  double prob = 0;
  int decision = -1;
  int64_t landmark = -1;  // input map_plane / map_line of a backbone structure record (-1 none)
};
struct OverlayInstanceState {  // trace records on i<frame>.<inst>
  bool has_prob = false;
  double prob = 0;
  int decision = -1;
};
// A loop closed in the frame (PROB loop.transform on kf<keyframe>, ref/loop/README.md "Trace").
struct OverlayLoop {
  int64_t keyframe = -1, loop_keyframe = -1;
  double moved_m = 0;  // how far the closing keyframe's centre moved
};
struct OverlayFrame {
  int64_t frame = -1;
  double timestamp = 0;
  std::string stamp_text;  // shown instead of timestamp when set (rgb.txt text)
  std::vector<OverlayFeature> features;  // observation order
  std::vector<OverlayShape> shapes;
  std::map<int, OverlayInstanceState> instances;
  std::vector<std::pair<std::string, int64_t>> counts;  // "stage.name", value (trace order)
  std::vector<OverlayLoop> loops;  // drawn as a magenta frame border and a "LOOP" banner
};
// Frames first..last (inclusive) that the trace contains, streaming the trace from the start
// (map-point probabilities carry over from earlier frames).
std::vector<OverlayFrame> CollectOverlayFrames(trace::TraceReader& reader, int64_t first, int64_t last);

// Ground truth of a synthetic sequence: SEQ/gt/ (dynref-detections folder with scene-wide
// instance ids) and SEQ/gt/moving.txt ("<rgb stamp> <moving instance ids...>").
class GroundTruthLabels {
 public:
  explicit GroundTruthLabels(const std::string& sequence_root);  // InputError if missing
  // Instance mask of the frame (CV_16U, empty if none) and its moving ids.
  bool Has(const std::string& stamp_text) const { return reader_.Has(stamp_text); }
  FrameDetections Read(const std::string& stamp_text) const { return reader_.Read(stamp_text); }
  std::set<int> Moving(const std::string& stamp_text) const;

 private:
  DetectionsReader reader_;
  std::map<std::string, std::set<int>> moving_;
};

struct GtFrame {
  cv::Mat instance_ids;  // CV_16U
  std::set<int> moving;
  bool IsDynamic(double u, double v) const;
};

// A method's mask layers of the frame (io/mask_layers.h): labels tinted in their legend colour.
struct MaskLayerView {
  cv::Mat labels;                          // CV_8U, empty = none this frame
  const std::vector<MaskLayer>* legend = nullptr;
};

// Draws one overlay. detections/gt/layers may be null.
Canvas RenderOverlay(const cv::Mat& bgr, const OverlayFrame& frame, const FrameDetections* detections,
                     const GtFrame* gt, const MaskLayerView* layers = nullptr);
// Tiles canvases (up to `columns` per row) on a dark background.
Canvas Montage(const std::vector<Canvas>& tiles, int columns);

struct OverlayOptions {
  bool gt = false;           // draw GT dynamic/static rings (needs SEQ/gt/)
  std::string out_dir;       // default RUN/overlays
  std::string montage_path;  // empty: no montage
  int montage_columns = 3;
};
// Renders frames first..last of a finished run to out_dir/overlay_<frame:06>.png (+ montage);
// returns the written paths. InputError for a bad run, missing sequence or frames out of range.
std::vector<std::string> RenderRunOverlays(const std::string& run_dir, int64_t first, int64_t last,
                                           const OverlayOptions& options);

}  // namespace dynref::render
