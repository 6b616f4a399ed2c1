// Data files of `dynref view` (README.md): one JavaScript file per run summary and per frame,
// each a call `VIEW.summaryZ(run, packed)` / `VIEW.chunkZ(run, n, heads, packed)` (packed.h), so that the page works
// from file:// (browsers refuse fetch() of local JSON, not <script src>). Records are the canonical
// flat view of ref/trace (the rows `dynref trace feature` prints), stored once per frame with a
// per-run table of record schemas (type, stage, kind, field names); numbers rounded to
// DataOptions::digits significant digits (17: exact).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "trace/trace_reader.h"

namespace dynref::view {

struct RunSite {
  std::string run_dir;     // the run folder given on the command line
  std::string label;       // shown in the page (folder name)
  std::vector<int64_t> frames;      // frame groups written (ascending)
  uint64_t data_bytes = 0;          // bytes of the data files written
};

struct DataOptions {
  int digits = 6;            // significant digits of the numbers written (17: exact)
  double image_scale = 0.5;  // overlay images' scale (the page maps clicks back to pixels)
  int chunk_frames = 30;     // frame groups per data file c<n>.js (one LZMA stream; README.md "Size")
  int threads = 1;           // chunks compressed at once (core/parallel.h: the same bytes for every N)
};

// Writes OUT/data/r<k>/summary.js, OUT/data/r<k>/links.js (the links of `trace feature --follow`) and OUT/data/r<k>/c<n>.js for every
// `chunk_frames` frame groups of the run's trace (the n-th chunk: groups n*K .. n*K+K-1). `image_for_frame` names each frame's overlay image relative to OUT ("" none).
// `divergence` (may be empty) is the first divergence against run 0, as `dynref diff` finds it.
RunSite WriteRunData(const std::string& run_dir, int k, const std::string& out_dir, const DataOptions& options,
                     const std::map<int64_t, std::string>& image_for_frame, const std::string& divergence_json);

}  // namespace dynref::view
