// Detection sources behind one interface (issue 7). A source turns one frame into
// dynref::FrameDetections (ref/io/mask_format.h, documented in datasets/MASK_FORMAT.md).
//
// Specs accepted by MakeDetectionSource (see ref/detect/README.md):
//   files:DIR       a dynref-detections folder (written by `dynref detect` / `dynref synth`)
//   labels:DIR      DynaSLAM-style import: per-frame label PNGs + DIR/labels.yaml (id -> class)
//   gt              SEQ/gt/ of a synthetic sequence (options.sequence_root)
//   gt:MODE         SEQ/detections/MODE/ of a synthetic sequence (ideal, yolo-like, ...)
//   nanodet         bundled NanoDet (COCO-80) + selfie person masks, OpenCV DNN on CPU
//   hog             OpenCV HOG people detector (boxes only, no network)
//   onnx-yolo[:M]   user YOLOv8/YOLO11 detect or seg ONNX (opset <= 12); M or options.model_path
//   onnx-maskrcnn[:M]  user torchvision Mask R-CNN ONNX (boxes, labels, scores, masks)
//   onnx-yolact[:M]    user YOLACT ONNX (loc, conf, mask coefficients, prototypes)
#pragma once
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "io/mask_format.h"

namespace dynref {

struct DetectSourceOptions {
  std::string sequence_root;    // needed by gt / gt:MODE; relative folders resolve against it
  std::string model_path;       // nanodet / onnx-yolo; empty = bundled model (nanodet)
  // Expected sha256 of model_path. Empty: the bundled hash for nanodet; onnx-yolo records the
  // hash without checking it. A mismatch is an InputError naming the file.
  std::string model_sha256;
  std::string mask_model_path;  // selfie segmenter for nanodet; empty = bundled
  double confidence_threshold = -1;  // < 0: the source's default (nanodet 0.3, onnx-yolo 0.25, hog 0.5)
  double nms_iou = 0.5;         // per-class NMS IoU threshold (nanodet, onnx-yolo)
  int max_detections = 100;     // per frame, after NMS
  bool masks = true;            // nanodet: person masks by selfie; onnx-yolo seg: instance masks
  int yolo_input_size = 640;    // square input size the YOLO model was exported with
  std::string class_names_file; // onnx-yolo: one class name per line (default COCO-80 if nc = 80)
  void Check() const;           // InputError naming the bad field (NaN thresholds included)
};

class DetectionSource {
 public:
  virtual ~DetectionSource() = default;
  // One token recorded in format.txt "source", e.g. "nanodet+selfie".
  virtual std::string name() const = 0;
  // Recorded in format.txt "model_sha256": the network hash(es) joined by '+', or "-".
  virtual std::string model_sha256() const = 0;
  // False for sources that read precomputed detections (image may then be empty).
  virtual bool needs_image() const = 0;
  // bgr: CV_8UC3 frame; stamp_text: rgb stamp exactly as in rgb.txt (key of precomputed sources).
  // Instances come out with ids 1..n in descending confidence; instance_ids is CV_16U of the
  // image size when some instance has a mask, else empty.
  virtual FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) = 0;
};

// Checks the spec's syntax without opening anything: a known source kind and its ':' argument
// (plus, for gt, the sequence root and, for onnx-yolo, a model). InputError naming `option`
// (e.g. "--source", "--detector").
void CheckDetectionSpec(const std::string& spec, const DetectSourceOptions& options,
                        const std::string& option = "<source>");

// Throws InputError for an unknown spec, a missing/corrupt folder or model, a wrong model sha256.
std::unique_ptr<DetectionSource> MakeDetectionSource(const std::string& spec,
                                                     const DetectSourceOptions& options);

// Bundled models (models/ in the source tree) and their sha256 (models/README.md).
std::string BundledModelPath(const std::string& file_name);
extern const char* const kNanodetSha256;
extern const char* const kSelfieSha256;

}  // namespace dynref
