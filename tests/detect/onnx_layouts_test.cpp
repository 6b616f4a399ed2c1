// The exact output layouts of the exports the README tells users to make (issue 39 item 4), each
// written as a tiny ONNX model (tiny_layout_onnx.h) and decoded through OpenCV DNN by the source
// a user would name: YOLOv8-seg / YOLO11-seg ([1, 116, 8400] + prototypes [1, 32, 160, 160]),
// YOLO11 / YOLOv8 detect ([1, 84, 8400] and its transpose), torchvision Mask R-CNN (boxes,
// labels, scores, masks) and YOLACT (loc, conf, mask, proto). A wrong layout is an InputError
// naming the model file (CLI exit 2), never a crash.
#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "detect/detection_source.h"
#include "detect/yolact_decode.h"
#include "test_support.h"
#include "tiny_layout_onnx.h"
#include "io/image_file.h"

using namespace dynref;
using test::LayoutOutput;
using test::SetFlatPixel;

namespace {

constexpr int kYoloSide = 640, kYoloAnchors = 8400;         // Ultralytics export at imgsz 640
constexpr float kBox = 640.f;  // box rows: 640 * pixel / 255 letterbox pixels

double BoxValue(int pixel) { return 640.0 * pixel / 255.0; }

// Box (cx, cy, w, h pixels), class score pixel at (row, anchor) of a channels x anchors layout.
struct YoloObject {
  int anchor, cx, cy, w, h, class_row, score;
};
void PutYolo(cv::Mat& img, const YoloObject& o, int channels, bool transposed) {
  const auto at = [&](int row) { return transposed ? int64_t(o.anchor) * channels + row : int64_t(row) * kYoloAnchors + o.anchor; };
  SetFlatPixel(img, at(0), o.cx);
  SetFlatPixel(img, at(1), o.cy);
  SetFlatPixel(img, at(2), o.w);
  SetFlatPixel(img, at(3), o.h);
  SetFlatPixel(img, at(o.class_row), o.score);
}

void CheckBox(const DetectedInstance& d, const YoloObject& o) {
  CHECK(d.x_min == Approx(BoxValue(o.cx) - BoxValue(o.w) / 2).margin(1e-3));
  CHECK(d.y_min == Approx(BoxValue(o.cy) - BoxValue(o.h) / 2).margin(1e-3));
  CHECK(d.x_max == Approx(BoxValue(o.cx) + BoxValue(o.w) / 2).margin(1e-3));
  CHECK(d.y_max == Approx(BoxValue(o.cy) + BoxValue(o.h) / 2).margin(1e-3));
  CHECK(d.confidence == Approx(o.score / 255.0).epsilon(1e-5));
}

const YoloObject kPerson{1000, 60, 96, 40, 64, 4 + 0, 230};   // person 0.90, box x 100-201, y 161-321
const YoloObject kChair{5000, 150, 100, 30, 30, 4 + 56, 153};  // chair 0.60
const YoloObject kFaint{7000, 50, 50, 10, 10, 4 + 0, 40};      // person 0.16 < 0.25: dropped

std::string Scratch(const std::string& name) { return test::ScratchDir("detect_onnx_layouts_" + name); }

}  // namespace

TEST_CASE("onnx layouts: YOLOv8-seg / YOLO11-seg export [1,116,8400] + [1,32,160,160] through onnx-yolo", "[cli]") {
  const std::string model = Scratch("seg") + "/yolo_seg.onnx";
  // Rows: 4 box (640 * pixel / 255), 80 class scores, 32 mask coefficients (x 4); prototypes 2 * pixel/255 - 1
  // from a 40 x 40 grid upsampled x4 (Ultralytics' proto head is stride 4: 160 = 640 / 4).
  test::WriteTinyLayoutOnnx(model, kYoloSide, kYoloSide,
                            {{"output0", {1, 116, kYoloAnchors}, {{4 * kYoloAnchors, kBox}, {80 * kYoloAnchors, 1}, {32 * kYoloAnchors, 4}}},
                             {"output1", {1, 32, 160, 160}, {{32 * 40 * 40, 2, -1}}, 4}});
  cv::Mat img = cv::Mat::zeros(kYoloSide, kYoloSide, CV_8UC3);
  for (const YoloObject& o : {kPerson, kChair, kFaint}) PutYolo(img, o, 116, false);
  SetFlatPixel(img, int64_t(84) * kYoloAnchors + kPerson.anchor, 255);  // person: coefficient 0 = 4, others 0
  const int64_t proto0 = int64_t(116) * kYoloAnchors;                    // prototype 0: +1 on grid rows 10-19, cols 8-15
  for (int y = 10; y < 20; ++y)
    for (int x = 8; x < 16; ++x) SetFlatPixel(img, proto0 + y * 40 + x, 255);

  DetectSourceOptions o;
  const FrameDetections f = MakeDetectionSource("onnx-yolo:" + model, o)->Detect(img, "seg");
  REQUIRE(f.instances.size() == 2);
  const DetectedInstance& person = f.instances[0];
  CHECK(person.class_name == "person");
  CHECK(person.class_id == 0);
  CheckBox(person, kPerson);
  CHECK(f.instances[1].class_name == "chair");
  CHECK(f.instances[1].class_id == 56);
  CheckBox(f.instances[1], kChair);
  // Person mask: sigmoid(4 * proto0) > 0.5 where the block (x 128-256, y 160-320) meets the box.
  REQUIRE(person.has_mask);
  CHECK_FALSE(f.instances[1].has_mask);  // all-zero coefficients: sigmoid(0) = 0.5, not > 0.5
  const cv::Mat m = f.MaskOf(person.id);
  CHECK(cv::countNonZero(m(cv::Rect(131, 164, 66, 153))) == 66 * 153);
  CHECK(m.at<uchar>(240, 110) == 0);  // in the box, outside the block
  CHECK(m.at<uchar>(240, 230) == 0);  // in the block, outside the box
  CHECK(cv::countNonZero(m) <= (201 - 126) * (324 - 157));
}

TEST_CASE("onnx layouts: YOLO11 / YOLOv8 detect export [1,84,8400] and its transpose [1,8400,84]") {
  for (const bool transposed : {false, true}) {
    INFO("transposed " << transposed);
    const std::string model = Scratch(transposed ? "det_t" : "det") + "/yolo_det.onnx";
    const std::vector<int64_t> shape = transposed ? std::vector<int64_t>{1, kYoloAnchors, 84} : std::vector<int64_t>{1, 84, kYoloAnchors};
    // Transposed: anchor-major, so one run of values x 1 (box pixels then read as pixel / 255).
    const std::vector<test::LayoutSegment> segs =
        transposed ? std::vector<test::LayoutSegment>{{int64_t(84) * kYoloAnchors, 1}}
                   : std::vector<test::LayoutSegment>{{4 * kYoloAnchors, kBox}, {80 * kYoloAnchors, 1}};
    test::WriteTinyLayoutOnnx(model, kYoloSide, kYoloSide, {{"output0", shape, segs}});
    cv::Mat img = cv::Mat::zeros(kYoloSide, kYoloSide, CV_8UC3);
    YoloObject p = kPerson;
    if (transposed) p = {kPerson.anchor, 200, 250, 100, 160, 4, 230};  // box values = pixel / 255
    PutYolo(img, p, 84, transposed);
    const FrameDetections f = MakeDetectionSource("onnx-yolo:" + model, {})->Detect(img, "det");
    REQUIRE(f.instances.size() == 1);
    CHECK(f.instances[0].class_name == "person");
    CHECK_FALSE(f.instances[0].has_mask);
    CHECK(f.instance_ids.empty());
    if (!transposed) CheckBox(f.instances[0], p);
    if (transposed) {
      CHECK(f.instances[0].x_min == Approx((200 - 50) / 255.0).margin(1e-4));
      CHECK(f.instances[0].y_max == Approx((250 + 80) / 255.0).margin(1e-4));
      CHECK(f.instances[0].confidence == Approx(230 / 255.0).epsilon(1e-5));
    }
  }
}

TEST_CASE("onnx layouts: a YOLO export of another layout is an InputError naming the model file", "[cli]") {
  const std::string dir = Scratch("bad");
  cv::Mat img = cv::Mat::zeros(kYoloSide, kYoloSide, CV_8UC3);
  // 8000 anchors (exported at another size than --input-size 640).
  test::WriteTinyLayoutOnnx(dir + "/wrong_size.onnx", kYoloSide, kYoloSide, {{"output0", {1, 85, 8000}, {{85 * 8000, 1}}}});
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-yolo:" + dir + "/wrong_size.onnx", {})->Detect(img, "x"),
                    Catch::Contains(dir + "/wrong_size.onnx") && Catch::Contains("no dimension of 8400 anchors"));
  // Three outputs: not a YOLO head.
  test::WriteTinyLayoutOnnx(dir + "/three.onnx", kYoloSide, kYoloSide,
                            {{"a", {1, 84, kYoloAnchors}, {{84 * kYoloAnchors, 1}}}, {"b", {1, 4}, {{4, 1}}}, {"c", {1, 4}, {{4, 1}}}});
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-yolo:" + dir + "/three.onnx", {}),
                    Catch::Contains(dir + "/three.onnx") && Catch::Contains("expected 1 (detect) or 2 (seg) outputs"));
  // The CLI: exit 2 with the file named, no crash.
  REQUIRE(dynref::ImageWrite(dir + "/frame.png", img));
  const test::CommandResult r = test::RunDynref("detect --source onnx-yolo:" + test::Quote(dir + "/wrong_size.onnx") +
                                                " --image " + test::Quote(dir + "/frame.png"));
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(dir + "/wrong_size.onnx") != std::string::npos);
}

TEST_CASE("onnx layouts: torchvision Mask R-CNN export (boxes, labels, scores, masks) through onnx-maskrcnn") {
  const std::string dir = Scratch("maskrcnn");
  const int w = 160, h = 120, n = 3;
  // boxes [3, 4] (160 * pixel / 255), labels [3] (pixel), scores [3] (pixel / 255), masks [3, 1, 120, 160]
  // from a 30 x 40 grid upsampled x4 (pixel / 255).
  const float kPx = 160.f;
  test::WriteTinyLayoutOnnx(dir + "/maskrcnn.onnx", h, w,
                            {{"boxes", {n, 4}, {{n * 4, kPx}}},
                             {"labels", {n}, {{n, 255}}},
                             {"scores", {n}, {{n, 1}}},
                             {"masks", {n, 1, h, w}, {{n * 30 * 40, 1}}, 4}});
  cv::Mat img = cv::Mat::zeros(h, w, CV_8UC3);
  const int boxes[n][4] = {{32, 16, 96, 112}, {112, 48, 150, 100}, {10, 10, 40, 40}};  // 160 * pixel / 255 image pixels
  const int labels[n] = {1, 62, 12};  // person, chair (91-id scheme), 12 = unused id ("N/A")
  const int scores[n] = {230, 150, 200};
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 4; ++k) SetFlatPixel(img, i * 4 + k, boxes[i][k]);
    SetFlatPixel(img, 12 + i, labels[i]);
    SetFlatPixel(img, 15 + i, scores[i]);
  }
  // Person mask plane: grid rows 5-19, cols 6-13 -> image y 20-79, x 24-55.
  for (int y = 5; y < 20; ++y)
    for (int x = 6; x < 14; ++x) SetFlatPixel(img, 18 + y * 40 + x, 255);
  const FrameDetections f = MakeDetectionSource("onnx-maskrcnn:" + dir + "/maskrcnn.onnx", {})->Detect(img, "mrcnn");
  REQUIRE(f.instances.size() == 2);  // label 12 is no COCO class
  const DetectedInstance& person = f.instances[0];
  CHECK(person.class_name == "person");
  CHECK(person.class_id == 0);
  CHECK(person.confidence == Approx(230 / 255.0).epsilon(1e-5));
  CHECK(person.x_min == Approx(32 * kPx / 255).margin(1e-3));
  CHECK(person.y_max == Approx(112 * kPx / 255).margin(1e-3));
  CHECK(f.instances[1].class_name == "chair");
  CHECK(f.instances[1].class_id == 56);
  REQUIRE(person.has_mask);
  CHECK_FALSE(f.instances[1].has_mask);  // all-zero plane
  const cv::Mat m = f.MaskOf(person.id);
  CHECK(cv::countNonZero(m) == 60 * 32);
  CHECK(cv::countNonZero(m(cv::Rect(24, 20, 32, 60))) == 60 * 32);

  // Masks not at the frame's size, or two outputs: InputError naming the model.
  test::WriteTinyLayoutOnnx(dir + "/small_masks.onnx", h, w,
                            {{"boxes", {n, 4}, {{n * 4, kPx}}},
                             {"labels", {n}, {{n, 255}}},
                             {"scores", {n}, {{n, 1}}},
                             {"masks", {n, 1, 30, 40}, {{n * 30 * 40, 1}}}});
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-maskrcnn:" + dir + "/small_masks.onnx", {})->Detect(img, "x"),
                    Catch::Contains(dir + "/small_masks.onnx") && Catch::Contains("masks are 40x30"));
  test::WriteTinyLayoutOnnx(dir + "/two.onnx", h, w, {{"boxes", {n, 4}, {{n * 4, kPx}}}, {"scores", {n}, {{n, 1}}}});
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-maskrcnn:" + dir + "/two.onnx", {})->Detect(img, "x"),
                    Catch::Contains(dir + "/two.onnx") && Catch::Contains("has 2 outputs"));
}

TEST_CASE("onnx layouts: YOLACT export (loc, conf, mask, proto) through onnx-yolact") {
  const std::string dir = Scratch("yolact");
  // Input 64: FPN cells 8, 4, 2, 1, 1 -> (64 + 16 + 4 + 1 + 1) * 3 = 258 priors; prototypes 16 x 16 x 4.
  const detect::YolactLayout layout = detect::YolactLayoutForInput(64);
  const cv::Mat priors = detect::YolactPriors(layout);
  REQUIRE(priors.rows == 258);
  REQUIRE(detect::YolactPriors(detect::YolactLayoutForInput(550)).rows == 19248);  // yolact_base
  const int p = 258, k = 4;
  // Every value comes from the R plane, normalised as (pixel - 123.68) / 58.40: each run undoes it
  // (x 58.40/255 + 123.68/255 = pixel / 255), then scales: loc 8 * pixel/255 - 4, conf pixel/255,
  // mask coefficients 8 * pixel/255 - 4, proto 2 * pixel/255 - 1.
  const float a = 58.40f / 255.f, b = 123.68f / 255.f;
  test::WriteTinyLayoutOnnx(dir + "/yolact.onnx", 64, 64,
                            {{"loc", {1, p, 4}, {{p * 4, 8 * a, 8 * b - 4}}},
                             {"conf", {1, p, 2}, {{p * 2, a, b}}},
                             {"mask", {1, p, k}, {{p * k, 8 * a, 8 * b - 4}}},
                             {"proto", {1, 16, 16, k}, {{16 * 16 * k, 2 * a, 2 * b - 1}}}});
  cv::Mat img = cv::Mat::zeros(64, 64, CV_8UC3);
  const auto r = [&](int64_t flat, int pixel) { img.at<cv::Vec3b>(int(flat / 64), int(flat % 64))[2] = uchar(pixel); };
  for (int64_t i = 0; i < p * 4; ++i) r(i, 128);                    // loc ~ 0 (pixel 128: 8 * 128/255 - 4 = 0.016)
  for (int64_t i = 0; i < p * k; ++i) r(p * 6 + i, 128);            // coefficients ~ 0
  const int q = 3 * (3 * 8 + 4);  // level 0, cell row 3, column 4, aspect ratio 1: centre (4.5/8, 3.5/8)
  r(p * 4 + q * 2 + 1, 230);      // person confidence 0.90 (column 1 = COCO class 0)
  r(p * 6 + q * k + 0, 255);      // coefficient 0 = 4
  const int64_t proto = p * (4 + 2 + k);
  for (int y = 4; y < 10; ++y)    // prototype 0 = +1 on rows 4-9, columns 6-11, -1 elsewhere
    for (int x = 6; x < 12; ++x) r(proto + (y * 16 + x) * k + 0, 255);

  DetectSourceOptions o;
  o.yolo_input_size = 64;
  const FrameDetections f = MakeDetectionSource("onnx-yolact:" + dir + "/yolact.onnx", o)->Detect(img, "yolact");
  REQUIRE(f.instances.size() == 1);
  const DetectedInstance& d = f.instances[0];
  CHECK(d.class_name == "person");
  CHECK(d.confidence == Approx(230 / 255.0).epsilon(1e-5));
  // Prior w = h = 24 / 64; loc 0.016 moves the centre by 0.016 * 0.1 * w and scales by exp(0.2 * 0.016).
  const double lv = 8 * 128 / 255.0 - 4;  // ~0.0157
  const double pw = 24.0 / 64, cx = 4.5 / 8 + lv * 0.1 * pw, w = pw * std::exp(lv * 0.2);
  CHECK(d.x_min == Approx((cx - w / 2) * 64).margin(0.01));
  CHECK(d.x_max == Approx((cx + w / 2) * 64).margin(0.01));
  REQUIRE(d.has_mask);
  const cv::Mat m = f.MaskOf(d.id);
  CHECK(m.at<uchar>(28, 34) == 255);  // inside the block (x 24-47, y 16-39) and the box
  CHECK(m.at<uchar>(50, 34) == 0);    // outside the block
  CHECK(cv::countNonZero(m) > 0);

  // The same model with --input-size 96 has the wrong prior count: InputError naming the model.
  o.yolo_input_size = 96;
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-yolact:" + dir + "/yolact.onnx", o)->Detect(img, "x"),
                    Catch::Contains(dir + "/yolact.onnx"));
}
