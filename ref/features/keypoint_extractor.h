// The feature plug-in point of the backbone (issue 17, Module B): one interface for every keypoint
// extractor, so tracking and local mapping see keypoints (octave = pyramid level), descriptors
// (binary CV_8U or L2-normalised CV_32F rows) and a DescriptorProfile (gates, orientation,
// pyramid) and nothing extractor-specific.
//   orb:  ORB-SLAM2's ORBextractor (orb_extractor.h), 256-bit rBRIEF, Hamming gates 50/100/64.
//   sift: OpenCV SIFT (Lowe 2004), 128 floats, squared-L2 gates (sift_extractor.cpp).
//   onnx: a SuperPoint-style network (score map + descriptor map) the user exports, e.g.
//         SuperPoint or ZippyPoint (onnx_extractor.h).
#pragma once
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "features/descriptor.h"
#include "features/orb_extractor.h"

namespace dynref::features {

struct SiftOptions {
  int n_features = 1000;           // backbone n_features (best responses kept)
  int octave_layers = 3;           // Lowe 2004 / OpenCV default
  double contrast_threshold = 0.04;
  double edge_threshold = 10;
  double sigma = 1.6;
};

struct OnnxOptions {
  std::string model;                           // .onnx file (cv::dnn::readNetFromONNX)
  std::string score_output = "scores";         // 1 x 65 x H/8 x W/8 logits (SuperPoint) or 1 x 1 x H x W
  std::string descriptor_output = "descriptors";  // 1 x D x Hd x Wd, sampled bilinearly
  int n_features = 1000;
  double score_threshold = 0.015;  // spec 004 step 2 (paper Sec. 4.1)
  int nms_radius = 3;              // spec 004 step 2 (paper Sec. 4.1)
  int border = 4;                  // SuperPoint's remove_borders default
  bool binary = false;             // pack descriptor signs into bits (ZippyPoint's binary head)
};

struct ExtractorOptions {
  std::string type = "orb";  // orb | sift | onnx
  OrbOptions orb;
  SiftOptions sift;
  OnnxOptions onnx;
  // Gates overriding the extractor's profile when > 0 (backbone descriptor_th_*).
  double th_low = 0, th_high = 0, th_reloc = 0;
  void Check() const;  // InputError naming the bad field
};

class KeypointExtractor {
 public:
  virtual ~KeypointExtractor() = default;
  // grey: CV_8U. Keypoints in image pixels with octave = level of profile()'s pyramid, angle in
  // degrees (oriented extractors) and response; one descriptor row per keypoint.
  virtual void Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors) = 0;
  virtual DescriptorProfile profile() const = 0;
  // Worker threads for extractors with a bit-identical parallel path (ORB); others ignore it.
  virtual void set_threads(int /*n*/) {}
};

// The extractor named by options.type, its profile's gates overridden by options.th_*.
// InputError for an unknown type or an unreadable model.
std::unique_ptr<KeypointExtractor> MakeExtractor(const ExtractorOptions& options);

}  // namespace dynref::features
