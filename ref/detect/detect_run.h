// `dynref detect` without the command line: precomputes per-frame detections of a sequence (or
// one image) into dynref's mask format (datasets/MASK_FORMAT.md), so a run is reproducible and
// the network runs once. The cli (cli/cmd_detect.cpp) only parses into DetectRunOptions.
#pragma once
#include <ostream>
#include <string>

#include "detect/detection_source.h"
#include "detect/temporal_links.h"

namespace dynref::detect {

// The options as `dynref detect` spells them (ref/detect/README.md).
struct DetectRunOptions {
  std::string source;                   // --source: nanodet | hog | onnx-yolo[:MODEL] | ... | gt[:MODE]
  std::string sequence, image;          // exactly one of them
  std::string out;                      // dynref-detections folder (required with --sequence)
  std::string camera, input, mode;      // camera preset/YAML; files/labels folder; gt mode
  std::string overlay, overlays;        // --image: overlay PNG; --sequence: folder of overlay PNGs
  std::string frames;                   // A, A-B or A- (empty: all)
  DetectSourceOptions options;
  TemporalOptions temporal{0};          // --temporal-gap 0: off (issue 39)
  bool no_masks = false;
  int repeat = 0;                       // --image: further timed runs (benchmark)
  bool conf_given = false, frames_given = false;  // the option was on the command line
};

// Checks every option before anything is opened (InputError naming the option), then detects
// the image or the sequence. Progress and results go to `out`, timings to `timing` only (never
// into the output folder: CONTRIBUTING, no wall clock in results).
void RunDetection(DetectRunOptions options, std::ostream& out, std::ostream& timing);

}  // namespace dynref::detect
