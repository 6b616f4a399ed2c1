// `dynref view RUN... --out DIR` (README.md): a self-contained static site (HTML + plain JS, no
// server, no CDN, opens from file://) to browse runs: a frame slider with each frame's overlay,
// a click on a feature (map point, line, mask) opens its whole history across frames with every
// stage's before -> after and inputs, decisions and residual weights; a per-run summary
// (run.json, trajectory vs ground truth, ATE over time, per-stage counts and timings); with two
// runs, the same entity in the second run and the first divergence as `dynref diff` finds it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dynref::view {

struct ViewOptions {
  std::vector<std::string> runs;  // run folders (the first is the oracle when several)
  std::string out_dir;
  bool overlays = true;           // render each frame's overlay (JPEG) when the sequence is readable
  int jpeg_quality = 60;          // README.md "Size": 15 % smaller than 70 at half size, labels still legible
  double image_scale = 0.5;       // overlay JPEG size relative to the frame (0.1..1)
  int digits = 6;                 // significant digits of the numbers in the data files (1..17; 17 exact)
  int chunk_frames = 30;          // frames per data file (one LZMA stream; 1..1000)
  int threads = 1;                // threads compressing data files (the same bytes for every N; 1..64)
  bool progress = false;          // frame i/N on stderr
  void Check() const;             // InputError naming the bad option
};

struct ViewResult {
  int64_t frames = 0, images = 0;
  uint64_t bytes = 0;  // everything written under out_dir
};

// Writes the site atomically: built in DIR.tmp.<pid>, then renamed onto DIR (an existing DIR
// written by an earlier `dynref view` is replaced; any other existing folder is refused).
ViewResult WriteSite(const ViewOptions& options);

}  // namespace dynref::view
