// dynref's detection/mask format (documented in datasets/MASK_FORMAT.md), written by
// `dynref synth --detections`, `dynref detect`, and read by every method:
//   DIR/format.txt    "dynref-detections 1", "source <name>", "model_sha256 <hex|->"
//   DIR/index.txt     one line per frame "<rgb stamp as in rgb.txt> <stem>", written LAST
//   DIR/<stem>.txt    one line per instance:
//                     "<id> <class_id> <class_name> <confidence> <x_min> <y_min> <x_max> <y_max> <has_mask>"
//   DIR/<stem>.png    16-bit instance-id PNG (0 = none, else the instance id); only when some
//                     instance of the frame has a mask
#pragma once
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dynref {

constexpr int kMaskFormatVersion = 1;

struct DetectedInstance {
  int id = 0;               // 1..65535, unique within the frame; pixel value in the PNG
  int class_id = -1;        // COCO id (see io/coco_classes.h), -1 unknown
  std::string class_name;   // one token
  double confidence = 1.0;
  double x_min = 0, y_min = 0, x_max = 0, y_max = 0;  // box in pixels
  bool has_mask = false;
};

struct FrameDetections {
  std::string stamp_text;                  // rgb stamp as in rgb.txt
  std::vector<DetectedInstance> instances; // ascending id
  cv::Mat instance_ids;                    // CV_16U or empty when no instance has a mask
  // The source that produced the scores (format.txt `source`, e.g. "nanodet+selfie"); stages map
  // a paper's threshold to it (detect/score_calibration.h). Empty = unknown (identity). Not on disk
  // per frame.
  std::string source;
  // Binary (CV_8U 0/255) mask of one instance; empty if it has none.
  cv::Mat MaskOf(int instance_id) const;
};

class DetectionsWriter {
 public:
  DetectionsWriter(const std::string& dir, const std::string& source, const std::string& model_sha256);
  // Stem defaults to the stamp text. Files are written atomically.
  void Write(const FrameDetections& frame);
  // Writes index.txt (atomically); until then the folder is incomplete and readers refuse it.
  void Finish();

 private:
  std::string dir_;
  std::vector<std::pair<std::string, std::string>> index_;  // stamp, stem
};

class DetectionsReader {
 public:
  explicit DetectionsReader(const std::string& dir);  // InputError if format/index is bad
  const std::string& source() const { return source_; }
  const std::string& model_sha256() const { return model_sha256_; }
  bool Has(const std::string& stamp_text) const { return index_.count(stamp_text) > 0; }
  std::vector<std::string> Stamps() const;  // ascending by value
  // InputError (naming file and line) for a malformed record, a duplicate instance id, a corrupt
  // PNG, or a PNG whose size differs from `image_size` (when given, i.e. non-empty).
  FrameDetections Read(const std::string& stamp_text, cv::Size image_size = {}) const;

 private:
  std::string dir_, source_, model_sha256_;
  std::map<std::string, std::string> index_;
};

}  // namespace dynref
