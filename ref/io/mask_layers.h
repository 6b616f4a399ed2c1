// Mask layers: per-frame 8-bit label images a method writes into its run folder so that
// `dynref overlay` can show which part of a mask came from where (seed 003: segmenter /
// compensation / depth fusion / dilation). Layout:
//   RUN/masks/legend.txt   "dynref-mask-layers 1", then one line per label "<value> <name> <r> <g> <b>"
//                          (value 1..255, name one token, colour 0..255), written LAST
//   RUN/masks/<rgb stamp>.png  CV_8U label per pixel (0 = none), frames without any label omitted
#pragma once
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dynref {

struct MaskLayer {
  int value = 0;
  std::string name;
  int r = 0, g = 0, b = 0;
};

// Collects PNG-encoded label images during a run (a few KB per frame) and writes them at the end.
class MaskLayersWriter {
 public:
  explicit MaskLayersWriter(std::vector<MaskLayer> legend);
  void Add(const std::string& stamp_text, const cv::Mat& labels);  // CV_8U; all-zero frames skipped
  // Writes dir/<stamp>.png for every frame, then dir/legend.txt (atomic files); returns frames written.
  size_t Write(const std::string& dir) const;

 private:
  std::vector<MaskLayer> legend_;
  std::map<std::string, std::vector<uchar>> png_;  // stamp -> encoded
};

class MaskLayersReader {
 public:
  // InputError naming the file and line for a malformed legend.
  explicit MaskLayersReader(const std::string& dir);
  static bool Exists(const std::string& dir);  // dir/legend.txt present
  const std::vector<MaskLayer>& legend() const { return legend_; }
  // The frame's labels (CV_8U), empty when the frame has none; InputError for an unreadable PNG or
  // one whose size differs from `size`.
  cv::Mat Read(const std::string& stamp_text, cv::Size size) const;

 private:
  std::string dir_;
  std::vector<MaskLayer> legend_;
};

}  // namespace dynref
