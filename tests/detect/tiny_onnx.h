// Writes a tiny ONNX model (hand-encoded protobuf, no ONNX library) with the output layout of
// a YOLOv8/YOLO11 seg export, so the onnx-yolo source can be tested end to end through OpenCV DNN:
//   images [1, 3, S, S] -> flatten -> output0 = [1, 4 + 1 + 1, A]  (box rows x 64, 1 class, 1 coeff)
//                                  -> output1 = [1, 1, S/4, S/4]   (one prototype)
// taken from consecutive values of the (R-channel) input, so an image with chosen pixel values
// makes the "network" predict a chosen box, score, coefficient and prototype.
#pragma once
#include <string>

namespace dynref::test {

constexpr double kTinyBoxScale = 64.0;  // box rows = 64 * pixel / 255

// Writes the model for input size s (multiple of 32) to path.
void WriteTinyYoloSegOnnx(const std::string& path, int s);

}  // namespace dynref::test
