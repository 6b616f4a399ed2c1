// Person masks for box detections with MediaPipe Selfie Segmentation (models/selfie.onnx):
// the segmenter runs on a square crop around each person box enlarged by 1.2 (models/README.md;
// it must not run on whole frames, where it marks person-like texture), its probability is
// resized back and pasted into the frame's 16-bit instance-id image.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

#include "detect/onnx_model.h"
#include "io/mask_format.h"

namespace dynref::detect {

struct PersonMaskOptions {
  double crop_enlarge = 1.2;     // square side = enlarge * max(box w, box h)
  double threshold = 0.5;        // person probability threshold
  double box_margin = 0.05;      // mask restricted to the box grown by this fraction per side
  int input_size = 256;          // selfie network input (1x3x256x256, RGB, /255)
};

// Square crop rectangle (may extend beyond the image) for a box.
cv::Rect PersonCropRect(const DetectedInstance& box, double enlarge);

// Pixels of image (zero padded outside) inside rect, as a new rect-sized image.
cv::Mat CropWithZeroPadding(const cv::Mat& image, const cv::Rect& rect);

// Paints one instance's probability map (CV_32F, crop-sized, placed at crop_rect) into the
// frame: pixel p inside allowed and inside the image goes to instance_id when prob > threshold
// and prob > best_prob(p) (strictly, so an earlier instance keeps ties). best_prob is CV_32F.
// Returns the number of pixels assigned by this call (a later instance may take some back).
int PaintInstanceProbability(const cv::Mat& prob, const cv::Rect& crop_rect, const cv::Rect& allowed,
                             int instance_id, double threshold, cv::Mat& instance_ids, cv::Mat& best_prob);

class PersonMasker {
 public:
  PersonMasker(LoadedModel model, PersonMaskOptions options = {});
  const std::string& sha256() const { return model_.sha256; }
  // Selfie probability (CV_32F, in [0,1]) of a square crop, at the crop's own size.
  cv::Mat CropProbability(const cv::Mat& crop_bgr);
  // Adds masks to the person instances (class_id 0) of frame, in ascending id order; instances
  // whose mask ends up empty keep has_mask = false. Sets frame.instance_ids when any mask exists.
  void AddMasks(const cv::Mat& bgr, FrameDetections& frame);

 private:
  LoadedModel model_;
  PersonMaskOptions options_;
};

}  // namespace dynref::detect
