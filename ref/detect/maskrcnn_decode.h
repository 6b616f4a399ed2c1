// Decoding of a torchvision Mask R-CNN ONNX export (maskrcnn_resnet50_fpn[_v2], exported with
// torch.onnx.export(..., output_names=["boxes", "labels", "scores", "masks"]) as torchvision's
// test/test_onnx.py does). Layout, from torchvision/models/detection/mask_rcnn.py (MaskRCNN
// docstring, "During inference ... returns ... boxes (FloatTensor[N, 4]) in [x1, y1, x2, y2]
// format, with 0 <= x1 < x2 <= W and 0 <= y1 < y2 <= H; labels (Int64Tensor[N]); scores
// (Tensor[N]); masks (UInt8Tensor[N, 1, H, W]) ... in 0-1 range ... thresholded, generally with a
// value of 0.5"):
//   boxes [N, 4] image pixels, labels [N] COCO category ids (1 = person, 91-id scheme with gaps),
//   scores [N] (already NMS-ed, descending), masks [N, 1, H, W] probabilities at the image size.
// N varies per image (0 is valid). Box/score/label/mask are already final: no anchors, no
// prototypes.
#pragma once
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/candidates.h"

namespace dynref::detect {

struct MaskRcnnOutputs {
  cv::Mat boxes;   // N x 4, CV_32F
  cv::Mat labels;  // N x 1, CV_32S (category ids as exported)
  cv::Mat scores;  // N x 1, CV_32F
  cv::Mat masks;   // N probability planes [N, 1, H, W] (or [N, H, W]), CV_32F; empty if absent
};

// The four outputs by name (boxes, labels, scores, masks) or, when the names are others, in
// torchvision's order. Three outputs (boxes, labels, scores) = a Faster R-CNN export (no masks).
// std::invalid_argument saying which output has which wrong shape.
MaskRcnnOutputs ArrangeMaskRcnnOutputs(const std::vector<cv::Mat>& outs, const std::vector<std::string>& names);

// torchvision's 91-id COCO category (1..90) to the 80-class index (0..79); -1 for background (0),
// the 11 unused ids (12, 26, 29, 30, 45, 66, 68, 69, 71, 83) and anything else.
int Coco91ToCoco80(int category_id);

// Candidates with score > score_threshold; class_id = Coco91ToCoco80(label) when class_count is
// 0, else label - 1 (a custom model: label 0 is background) and labels outside 1..class_count
// are skipped; anchor = row. Boxes clipped to the image.
std::vector<Candidate> DecodeMaskRcnnBoxes(const MaskRcnnOutputs& out, cv::Size image, double score_threshold,
                                           int class_count = 0);

// Instance mask of row `anchor`: probability >= 0.5 (CV_8U 0/255 of the image size).
// std::invalid_argument when the mask plane is not image-sized.
cv::Mat DecodeMaskRcnnMask(const MaskRcnnOutputs& out, int anchor, cv::Size image);

}  // namespace dynref::detect
