// The onnx-yolo source end to end through OpenCV DNN on a tiny hand-built "seg model" whose
// outputs are chosen pixels of the input image (tiny_onnx.h).
#include <catch2/catch.hpp>
#include <opencv2/core.hpp>
#include <fstream>

#include "core/error.h"
#include "core/sha256.h"
#include "detect/detection_source.h"
#include "test_support.h"
#include "tiny_onnx.h"

using namespace dynref;

namespace {

constexpr int kS = 64, kAnchors = 64 + 16 + 4;

// Sets the value the tiny model reads at flat position k (R channel = BGR channel 2).
void SetFlat(cv::Mat& bgr, int k, int pixel) { bgr.at<cv::Vec3b>(k / kS, k % kS)[2] = uchar(pixel); }

double Box(int pixel) { return test::kTinyBoxScale * pixel / 255.0; }

}  // namespace

TEST_CASE("onnx-yolo: tiny seg model through OpenCV DNN gives the encoded box, class and mask") {
  const std::string dir = test::ScratchDir("detect_onnx_yolo");
  const std::string model = dir + "/tiny_seg.onnx";
  test::WriteTinyYoloSegOnnx(model, kS);
  cv::Mat img = cv::Mat::zeros(kS, kS, CV_8UC3);
  const int a = 10;                 // anchor carrying the object
  SetFlat(img, 0 * kAnchors + a, 128);  // cx
  SetFlat(img, 1 * kAnchors + a, 128);  // cy
  SetFlat(img, 2 * kAnchors + a, 80);   // w
  SetFlat(img, 3 * kAnchors + a, 160);  // h
  SetFlat(img, 4 * kAnchors + a, 230);  // class-0 score 0.90
  SetFlat(img, 5 * kAnchors + a, 255);  // mask coefficient 1
  SetFlat(img, 4 * kAnchors + 40, 30);  // another anchor, score 0.12 < 0.25
  // Prototype (16 x 16, values 0 or 1): 1 on proto rows 4..11, columns 6..9.
  for (int y = 4; y < 12; ++y)
    for (int x = 6; x < 10; ++x) SetFlat(img, 6 * kAnchors + y * 16 + x, 255);

  DetectSourceOptions o;
  o.yolo_input_size = kS;
  auto src = MakeDetectionSource("onnx-yolo:" + model, o);
  CHECK(src->name() == "onnx-yolo");
  CHECK(src->model_sha256() == Sha256File(model));
  const FrameDetections f = src->Detect(img, "tiny");
  REQUIRE(f.instances.size() == 1);
  const DetectedInstance& d = f.instances[0];
  CHECK(d.class_name == "class_0");  // 1 class and no --class-names
  CHECK(d.class_id == -1);
  CHECK(d.confidence == Approx(230 / 255.0).epsilon(1e-6));
  CHECK(d.x_min == Approx(Box(128) - Box(80) / 2).epsilon(1e-5));
  CHECK(d.y_min == Approx(Box(128) - Box(160) / 2).epsilon(1e-5));
  CHECK(d.x_max == Approx(Box(128) + Box(80) / 2).epsilon(1e-5));
  CHECK(d.y_max == Approx(Box(128) + Box(160) / 2).epsilon(1e-5));
  REQUIRE(d.has_mask);
  // sigmoid(1) > 0.5 inside the prototype block (image x 24..39, y 16..47), sigmoid(0) = 0.5 outside.
  const cv::Mat m = f.MaskOf(1);
  CHECK(m.at<uchar>(30, 30) == 255);
  CHECK(m.at<uchar>(30, 45) == 0);
  CHECK(m.at<uchar>(8, 30) == 0);
  CHECK(cv::countNonZero(m(cv::Rect(26, 18, 12, 28))) == 12 * 28);
  // Bilinear upsampling (x4) lets the block grow by < 2 px per side where the probability of the
  // blend stays above 0.5.
  CHECK(cv::countNonZero(m) >= 16 * 32);
  CHECK(cv::countNonZero(m) <= (16 + 4) * (32 + 4));

  // Class names file: the one class is "person" -> COCO id 0. Wrong count -> InputError.
  std::ofstream(dir + "/names.txt") << "person\n";
  o.class_names_file = dir + "/names.txt";
  const FrameDetections named = MakeDetectionSource("onnx-yolo:" + model, o)->Detect(img, "tiny");
  REQUIRE(named.instances.size() == 1);
  CHECK(named.instances[0].class_id == 0);
  std::ofstream(dir + "/names2.txt") << "person\nchair\n";
  o.class_names_file = dir + "/names2.txt";
  CHECK_THROWS_AS(MakeDetectionSource("onnx-yolo:" + model, o)->Detect(img, "tiny"), InputError);
  // Boxes only when masks are off; wrong sha is refused; wrong input size is a clear error.
  o.class_names_file.clear();
  o.masks = false;
  const FrameDetections boxes = MakeDetectionSource("onnx-yolo:" + model, o)->Detect(img, "tiny");
  CHECK_FALSE(boxes.instances.at(0).has_mask);
  CHECK(boxes.instance_ids.empty());
  o.model_sha256 = std::string(64, 'a');
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-yolo:" + model, o), Catch::Contains("sha256 mismatch"));
  o.model_sha256.clear();
  o.yolo_input_size = 96;
  CHECK_THROWS_AS(MakeDetectionSource("onnx-yolo:" + model, o)->Detect(img, "tiny"), InputError);
}
