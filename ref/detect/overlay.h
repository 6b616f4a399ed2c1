// Picture of one frame's detections for a person to look at: masks tinted per instance, boxes,
// "class confidence" labels. Pure OpenCV drawing (Hershey font), deterministic.
#pragma once
#include <opencv2/core.hpp>

#include "io/mask_format.h"

namespace dynref::detect {

// Returns a BGR copy of image with the detections drawn; mask_alpha = tint opacity.
cv::Mat DrawDetections(const cv::Mat& bgr, const FrameDetections& frame, double mask_alpha = 0.45);

}  // namespace dynref::detect
