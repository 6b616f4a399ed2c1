// What a stage or map module leaves at the end of a run: the files it wrote into the run folder
// (reported in run.json "outputs") and, if it failed, its error (run.json "output_errors",
// end_state "error: ...", exit 2).
#pragma once
#include <string>
#include <vector>

namespace dynref {

struct RunOutput {
  std::string module;  // stage / map module name
  std::string path;    // relative to the run folder when inside it, else as written
  std::string what;    // one line: what the file holds
};

// How many detections of a stage's dynamic classes it saw over the run and how many its
// confidence threshold dropped (issue 39; run.json "detections_used", the end-of-run line, and a
// warning when most were dropped).
struct DetectionUse {
  std::string stage;               // e.g. "blur.mask"
  std::string key;                 // the threshold's config key, e.g. "min_confidence"
  std::string scale;               // "detector" (calibrated to the source) or "raw"
  std::string source;              // detection source of the run ("" when no frame had detections)
  double paper_threshold = 0;      // the key's value
  double applied_threshold = 0;    // what raw confidences were compared with
  int64_t seen = 0;                // detections of a dynamic class
  int64_t dropped = 0;             // of those, below the threshold
  bool MostDropped() const { return seen > 0 && 2 * dropped > seen; }
};

class RunEnd {
 public:
  explicit RunEnd(std::string out_dir) : out_dir_(std::move(out_dir)) {}
  // The run folder (empty when a stage is driven outside `dynref run`: write nothing then).
  const std::string& out_dir() const { return out_dir_; }
  // A path inside out_dir() is recorded relative to it (the run folder is written in a staging
  // folder and renamed into place at the end, so its absolute path changes).
  void AddOutput(const std::string& module, const std::string& path, const std::string& what) {
    const std::string prefix = out_dir_ + "/";
    const bool inside = !out_dir_.empty() && path.compare(0, prefix.size(), prefix) == 0;
    outputs_.push_back({module, inside ? path.substr(prefix.size()) : path, what});
  }
  const std::vector<RunOutput>& outputs() const { return outputs_; }
  void AddDetectionUse(const DetectionUse& use) { detection_use_.push_back(use); }
  const std::vector<DetectionUse>& detection_use() const { return detection_use_; }

 private:
  std::string out_dir_;
  std::vector<RunOutput> outputs_;
  std::vector<DetectionUse> detection_use_;
};

}  // namespace dynref
