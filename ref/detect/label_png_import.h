// Import of per-frame label PNGs, the export most DynaSLAM / Mask R-CNN / YOLO-seg users have:
//   DIR/labels.yaml   table of pixel value -> class (see ref/detect/README.md):
//                       png_kind: instance      # or: semantic
//                       confidence: 1.0         # optional, recorded for every instance
//                       min_area_px: 1          # optional, smaller regions are dropped
//                       labels: {1: person, 2: chair}
//   DIR/<rgb stamp>.png   8- or 16-bit single channel, 0 = background, image-sized.
// instance: each distinct non-zero value is one instance of the class the table gives it;
// semantic: each 8-connected region of one value is one instance.
#pragma once
#include <map>
#include <string>

#include "io/mask_format.h"

namespace dynref::detect {

struct LabelTable {
  bool semantic = false;
  double confidence = 1.0;
  int min_area_px = 1;
  std::map<int, std::string> labels;  // pixel value -> class name (one token)
};

// InputError naming the file (and line when yaml-cpp knows it) for a malformed table.
LabelTable ReadLabelTable(const std::string& yaml_path);

// Instances (ids 1..n by ascending pixel value, then region raster order), boxes = pixel-edge
// bounding boxes [x, x + w] x [y, y + h]. InputError for a missing/corrupt PNG, a multi-channel
// PNG or a value missing from the table.
FrameDetections ReadLabelPng(const LabelTable& table, const std::string& png_path,
                             const std::string& stamp_text);

}  // namespace dynref::detect
