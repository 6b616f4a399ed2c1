// `dynref overview` (the main job, issue 36): every method on one embedded synthetic sequence,
// evaluated against its ground truth, in one Markdown page: ATE / RPE, tracked frames, ms per
// frame per module, rejection precision / recall against the ground-truth motion labels, the map
// files each run wrote, a top view of every trajectory, the same frame's overlay per method side
// by side, and the link to the `dynref view` site of the runs.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dynref::reproduce {

struct OverviewArgs {
  std::string out = "out/demo/overview.md";  // the page; plots and the montage beside it
  std::string work = "out/demo/work";        // sequence and runs (<work>/seed<S>/{seq,runs})
  std::string preset = "walking_xyz";
  int frames = 150;
  uint64_t seed = 1;
  std::vector<std::string> methods = {"orb", "sgdo", "mgd", "mgd-nd", "blur", "epi", "semantic"};
  std::string viewer;     // relative link to the viewer's index.html ("" = none)
  int overlay_frame = -1;  // -1: the middle frame
  bool reuse = false;
  void Check() const;
};

// Runs what is missing, writes `out`; returns the exit code (0, or 1 when a run did not finish).
int RunOverview(const OverviewArgs& args);

}  // namespace dynref::reproduce
