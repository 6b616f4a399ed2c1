// Constructors of the concrete detection sources (internal to the detect room; everything
// outside uses MakeDetectionSource in detection_source.h).
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "detect/candidates.h"
#include "detect/detection_source.h"

namespace dynref::detect {

std::unique_ptr<DetectionSource> MakeNanodetSource(const DetectSourceOptions& options);
std::unique_ptr<DetectionSource> MakeHogSource(const DetectSourceOptions& options);
std::unique_ptr<DetectionSource> MakeOnnxYoloSource(const std::string& model_path,
                                                    const DetectSourceOptions& options);
// kind "onnx-maskrcnn" (torchvision Mask R-CNN) or "onnx-yolact" (onnx_instance_source.cpp).
std::unique_ptr<DetectionSource> MakeOnnxInstanceSource(const std::string& kind, const std::string& model_path,
                                                        const DetectSourceOptions& options);
// A dynref-detections folder; name()/model_sha256() pass through what the folder records.
std::unique_ptr<DetectionSource> MakeFolderSource(const std::string& dir);
// DynaSLAM-style label PNG folder (see label_png_import.h).
std::unique_ptr<DetectionSource> MakeLabelPngSource(const std::string& dir);

// InputError unless bgr is a non-empty CV_8UC3 image (names the frame).
void RequireBgrImage(const cv::Mat& bgr, const std::string& stamp_text, const std::string& source);

// Candidates (already in output order) to instances with ids 1..n, classes named by
// class_names (index = candidate class; COCO id looked up by name, -1 if not COCO).
FrameDetections CandidatesToFrame(const std::vector<Candidate>& kept, const std::string& stamp_text,
                                  const std::vector<std::string>& class_names);
std::vector<std::string> CocoClassNames();
// Paints mask_of(kept[i]) into frame.instance_ids with instance i's id, in ascending confidence so
// the most confident instance owns overlaps; sets each instance's has_mask, and instance_ids only
// when some instance kept pixels. frame is CandidatesToFrame(kept, ...).
void PaintInstanceMasks(const std::vector<Candidate>& kept, cv::Size image,
                        const std::function<cv::Mat(const Candidate&)>& mask_of, FrameDetections& frame);

}  // namespace dynref::detect
