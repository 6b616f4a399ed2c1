// The inputs of one run, opened and checked before anything is written (bad input here throws
// InputError: exit 2, nothing written): the resolved method config, the sequence and its camera,
// the detections (precomputed folder or a detector), and the frames to process.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "detect/detection_source.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "pipeline/method_config.h"
#include "pipeline/pipeline.h"

namespace dynref {

struct RunInputs {
  std::shared_ptr<const MethodConfig> config;
  Sequence sequence;
  std::vector<FrameEntry> frames;                   // the --frames selection, sequence order
  std::unique_ptr<DetectionsReader> det_reader;     // --detections DIR
  std::unique_ptr<DetectionSource> det_source;      // --detector SPEC
  std::string detector_name = "none";               // "<source> sha256:<model>"
  std::string sequence_abs, detections_abs;         // absolute paths (reports open runs from anywhere)

  // Loads rgb, depth and detections of one frame into f (InputError on unreadable input).
  void LoadFrame(const FrameEntry& e, const RunOptions& options, Frame& f, FrameDetections& dets) const;
};

// The config and the sequence (before the method's components are created from the config).
RunInputs OpenRunInputs(const RunOptions& options);
// Then the detections and the --frames selection.
void OpenDetections(const RunOptions& options, RunInputs& in);

}  // namespace dynref
