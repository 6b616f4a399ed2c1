// `dynref synth`: writes a synthetic dynamic RGB-D sequence in the exact TUM RGB-D layout plus
// per-pixel ground truth (gt/) and optional degraded detections (detections/<mode>/).
// Layout and models are documented in datasets/README.md.
#pragma once
#include <cstdint>
#include <string>

namespace dynref::synth {

// Upper bound of --frames: 100000 frames are 55 minutes at 30 Hz, ~40x the longest preset default
// (~1260) and already ~100 GB of PNGs; a larger count is a typo, not a sequence anyone wants (and
// it would run for days before failing on a full disk).
constexpr int kMaxFrames = 100000;
// Smallest --width: 64x48 is the smallest image `dynref run` accepts.
constexpr int kMinWidth = 64;

struct SynthOptions {
  std::string preset;             // see PresetNames()
  int frames = 0;                 // 0 = the preset's default length; at most kMaxFrames
  int width = 0;                  // 0 = the camera's 640; else kMinWidth..640, a multiple of 4
                                  // (height 3/4 of it, intrinsics scaled): cheap smoke sequences
  uint64_t seed = 1;
  bool blur = false;              // integrate sub-frame renders over the exposure
  bool low_light = false;
  std::string detections = "none";  // none | ideal | yolo-like | sparseinst-like | all
  std::string out;
  int blur_subframes = 8;
  double exposure_s = 1.0 / 30.0;
  void Check() const;             // InputError naming the bad field
};

struct SynthStats {
  int frames = 0;
  double render_ms_per_frame = 0;  // rasterise + shade (+ blur sub-frames) + sensor model (wall)
  double render_cpu_ms_per_frame = 0;  // same, process CPU time
  double total_ms_per_frame = 0;   // everything incl. GT, detections and PNG encoding (wall)
  double total_cpu_ms_per_frame = 0;  // same, process CPU time (one thread: = one core)
};

// Builds the sequence in the sibling temp folder "<out>.tmp.<pid>" and renames it onto out only
// when complete. An existing out is replaced when it is empty or a dynref synth output (has a
// synth.yaml naming the generator); anything else is refused with an InputError.
SynthStats GenerateSequence(const SynthOptions& options);

// Timestamp of frame i (seconds, TUM style) and its rendering time t (seconds since frame 0).
constexpr double kStampBase = 1700000000.0;
constexpr double kFrameRateHz = 30.0;

}  // namespace dynref::synth
