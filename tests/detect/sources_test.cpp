// Precomputed sources (files, gt, labels importer), the HOG fallback, and the errors a user
// meets: unknown source, bad model path, wrong sha256, corrupt PNG, mis-sized mask, bad table.
#include <catch2/catch.hpp>
#include <fstream>
#include <sys/stat.h>

#include "core/error.h"
#include "detect/detection_source.h"
#include "detect/label_png_import.h"
#include "test_support.h"
#include "io/image_file.h"

using namespace dynref;
using dynref::test::ScratchDir;
using dynref::test::SourcePath;
using dynref::test::WriteText;

namespace {

FrameDetections SampleFrame(const std::string& stamp) {
  FrameDetections f;
  f.stamp_text = stamp;
  DetectedInstance a;
  a.id = 1;
  a.class_id = 0;
  a.class_name = "person";
  a.confidence = 0.73125;
  a.x_min = 10.25;
  a.y_min = 20.5;
  a.x_max = 40.125;
  a.y_max = 70.0625;
  a.has_mask = true;
  DetectedInstance b = a;
  b.id = 2;
  b.class_id = 56;
  b.class_name = "chair";
  b.confidence = 1.0 / 3.0;
  b.has_mask = false;
  f.instances = {a, b};
  f.instance_ids = cv::Mat::zeros(48, 64, CV_16U);
  f.instance_ids(cv::Rect(11, 21, 29, 20)).setTo(1);
  return f;
}

void WriteFolder(const std::string& dir, const std::vector<std::string>& stamps, const std::string& source) {
  DetectionsWriter w(dir, source, "-");
  for (const auto& s : stamps) w.Write(SampleFrame(s));
  w.Finish();
}

}  // namespace

TEST_CASE("sources: files source round-trips the mask format exactly") {
  const std::string dir = ScratchDir("detect_files_roundtrip") + "/det";
  WriteFolder(dir, {"1305031453.359684", "1305031453.391690"}, "nanodet+selfie");
  auto src = MakeDetectionSource("files:" + dir, {});
  CHECK(src->name() == "nanodet+selfie");
  CHECK(src->model_sha256() == "-");
  CHECK_FALSE(src->needs_image());
  const FrameDetections want = SampleFrame("1305031453.391690");
  const FrameDetections got = src->Detect(cv::Mat(), "1305031453.391690");
  REQUIRE(got.instances.size() == 2);
  for (size_t i = 0; i < 2; ++i) {
    CHECK(got.instances[i].id == want.instances[i].id);
    CHECK(got.instances[i].class_id == want.instances[i].class_id);
    CHECK(got.instances[i].class_name == want.instances[i].class_name);
    CHECK(got.instances[i].confidence == want.instances[i].confidence);  // bit-exact
    CHECK(got.instances[i].x_min == want.instances[i].x_min);
    CHECK(got.instances[i].y_min == want.instances[i].y_min);
    CHECK(got.instances[i].x_max == want.instances[i].x_max);
    CHECK(got.instances[i].y_max == want.instances[i].y_max);
    CHECK(got.instances[i].has_mask == want.instances[i].has_mask);
  }
  CHECK(cv::countNonZero(got.instance_ids != want.instance_ids) == 0);
  CHECK(cv::countNonZero(got.MaskOf(1)) == 29 * 20);
  CHECK_THROWS_AS(src->Detect(cv::Mat(), "1305031453.999999"), InputError);  // frame not in index
  // A frame whose size differs from the mask's is refused.
  CHECK_THROWS_AS(src->Detect(cv::Mat(480, 640, CV_8UC3), "1305031453.391690"), InputError);
}

TEST_CASE("sources: gt and gt:MODE read a synthetic sequence's folders") {
  const std::string seq = ScratchDir("detect_gt_seq");
  ::mkdir((seq + "/detections").c_str(), 0755);
  WriteFolder(seq + "/gt", {"0.000000"}, "gt");
  WriteFolder(seq + "/detections/yolo-like", {"0.000000"}, "yolo-like");
  DetectSourceOptions o;
  o.sequence_root = seq;
  CHECK(MakeDetectionSource("gt", o)->name() == "gt");
  auto degraded = MakeDetectionSource("gt:yolo-like", o);
  CHECK(degraded->name() == "yolo-like");
  CHECK(degraded->Detect(cv::Mat(), "0.000000").instances.size() == 2);
  CHECK_THROWS_AS(MakeDetectionSource("gt:sparseinst-like", o), InputError);  // not generated
  CHECK_THROWS_AS(MakeDetectionSource("gt", {}), InputError);                 // no sequence
}

TEST_CASE("sources: corrupt or missing instance PNG is a clear InputError") {
  const std::string dir = ScratchDir("detect_corrupt_png") + "/det";
  WriteFolder(dir, {"1.0"}, "test");
  WriteText(dir + "/1.0.png", "this is not a PNG");
  auto src = MakeDetectionSource("files:" + dir, {});
  try {
    src->Detect(cv::Mat(), "1.0");
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("corrupt") != std::string::npos);
    CHECK(e.file() == dir + "/1.0.png");
  }
  CHECK_THROWS_AS(MakeDetectionSource("files:" + dir + "/nope", {}), InputError);
}

TEST_CASE("sources: DynaSLAM-style label PNGs with a YAML table") {
  const std::string dir = ScratchDir("detect_labels");
  cv::Mat lab = cv::Mat::zeros(40, 60, CV_8U);
  lab(cv::Rect(5, 6, 10, 12)).setTo(3);    // person
  lab(cv::Rect(40, 20, 8, 8)).setTo(3);    // a second person region
  lab(cv::Rect(20, 25, 6, 4)).setTo(7);    // chair
  REQUIRE(dynref::ImageWrite(dir + "/100.5.png", lab));
  WriteText(dir + "/labels.yaml", "png_kind: semantic\nconfidence: 0.9\nlabels:\n  3: person\n  7: chair\n");
  auto src = MakeDetectionSource("labels:" + dir, {});
  CHECK(src->name() == "labels");
  const FrameDetections f = src->Detect(cv::Mat(40, 60, CV_8UC3), "100.5");
  REQUIRE(f.instances.size() == 3);
  CHECK(f.instances[0].class_name == "person");
  CHECK(f.instances[0].class_id == 0);
  CHECK(f.instances[0].x_min == 5);
  CHECK(f.instances[0].y_min == 6);
  CHECK(f.instances[0].x_max == 14);  // inclusive extreme pixels (MASK_FORMAT.md; issue 20 item 11)
  CHECK(f.instances[0].y_max == 17);
  CHECK(f.instances[0].confidence == 0.9);
  CHECK(f.instances[1].class_name == "person");
  CHECK(f.instances[1].x_min == 40);
  CHECK(f.instances[2].class_name == "chair");
  CHECK(f.instances[2].class_id == 56);
  CHECK(cv::countNonZero(f.MaskOf(3)) == 24);
  // Instance kind: all pixels of one value are one instance.
  WriteText(dir + "/labels.yaml", "png_kind: instance\nlabels: {3: person, 7: chair}\n");
  CHECK(MakeDetectionSource("labels:" + dir, {})->Detect(cv::Mat(), "100.5").instances.size() == 2);
  // A value missing from the table, a corrupt PNG, a malformed table.
  WriteText(dir + "/labels.yaml", "labels: {3: person}\n");
  CHECK_THROWS_WITH(MakeDetectionSource("labels:" + dir, {})->Detect(cv::Mat(), "100.5"),
                    Catch::Contains("pixel value 7"));
  WriteText(dir + "/labels.yaml", "labels: {3: person, 7: chair}\n");
  WriteText(dir + "/100.5.png", "garbage");
  CHECK_THROWS_WITH(MakeDetectionSource("labels:" + dir, {})->Detect(cv::Mat(), "100.5"),
                    Catch::Contains("corrupt"));
  WriteText(dir + "/labels.yaml", "png_kind: polygons\nlabels: {1: person}\n");
  CHECK_THROWS_AS(MakeDetectionSource("labels:" + dir, {}), InputError);
  WriteText(dir + "/labels.yaml", "labels: [person, chair\n");
  CHECK_THROWS_AS(MakeDetectionSource("labels:" + dir, {}), InputError);
}

TEST_CASE("sources: model loading checks path and sha256") {
  DetectSourceOptions bad_path;
  bad_path.model_path = "/nonexistent/nanodet.onnx";
  CHECK_THROWS_WITH(MakeDetectionSource("nanodet", bad_path), Catch::Contains("/nonexistent/nanodet.onnx") &&
                                                                  Catch::Contains("not found"));
  DetectSourceOptions wrong_file;
  wrong_file.model_path = SourcePath("models/selfie.onnx");  // a real model, but not NanoDet
  CHECK_THROWS_WITH(MakeDetectionSource("nanodet", wrong_file), Catch::Contains("sha256 mismatch"));
  DetectSourceOptions wrong_sha;
  wrong_sha.model_path = SourcePath("models/nanodet.onnx");
  wrong_sha.model_sha256 = std::string(64, '0');
  CHECK_THROWS_WITH(MakeDetectionSource("nanodet", wrong_sha), Catch::Contains("sha256 mismatch"));
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-yolo", {}), Catch::Contains("needs a model"));
  CHECK_THROWS_WITH(MakeDetectionSource("onnx-yolo:" + SourcePath("models/README.md"), {}),
                    Catch::Contains("not a loadable ONNX"));
  CHECK_THROWS_WITH(MakeDetectionSource("yolo", {}), Catch::Contains("unknown detection source"));
  DetectSourceOptions bad_iou;
  bad_iou.nms_iou = 0;
  CHECK_THROWS_WITH(MakeDetectionSource("hog", bad_iou), Catch::Contains("nms_iou"));
}

TEST_CASE("sources: HOG people detector finds the person on person.jpg and none among horses") {
  auto hog = MakeDetectionSource("hog", {});
  const FrameDetections f = hog->Detect(dynref::ImageRead(SourcePath("tests/data/darknet/person.jpg")), "person");
  REQUIRE(f.instances.size() >= 1);
  const auto& d = f.instances[0];
  CHECK(d.class_name == "person");
  CHECK_FALSE(d.has_mask);
  // The HOG window has a margin around the body: the hand box (191..274, 99..372) lies inside.
  CHECK(d.x_min < 191);
  CHECK(d.x_max > 274);
  CHECK(d.y_min < 99);
  CHECK(d.y_max > 372);
  CHECK(d.x_max - d.x_min < 2.5 * (274 - 191));
  CHECK(hog->Detect(dynref::ImageRead(SourcePath("tests/data/darknet/horses.jpg")), "horses").instances.empty());
}

TEST_CASE("sources: HOG on images smaller than its 64x128 window gives no detections (issue 37)") {
  // OpenCV 4.6's detectMultiScale always evaluates its first pyramid level: on an image smaller
  // than the window it corrupted the heap (16x16, 32x32, 64x48: SIGSEGV / glibc abort, varying)
  // or asserted (48x64). Under ASan / valgrind the out-of-bounds accesses are reported.
  auto hog = MakeDetectionSource("hog", {});
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(16, 16), cv::Size(32, 32), cv::Size(48, 64), cv::Size(64, 48),
                              cv::Size(96, 72), cv::Size(63, 128), cv::Size(64, 127), cv::Size(200, 100)}) {
    INFO(size.width << "x" << size.height);
    cv::Mat img(size, CV_8UC3);
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) img.at<cv::Vec3b>(y, x) = cv::Vec3b(uint8_t(x * 7), uint8_t(y * 13), uint8_t(x * y));
    FrameDetections f;
    REQUIRE_NOTHROW(f = hog->Detect(img, "small"));
    CHECK(f.instances.empty());
  }
  // The window itself (64x128) is searched as before.
  cv::Mat window(128, 64, CV_8UC3, cv::Scalar(90, 90, 90));
  CHECK_NOTHROW(hog->Detect(window, "window"));
}

TEST_CASE("mask format: a class_id outside COCO is rejected with file and line (issue 20 item 11)") {
  const std::string dir = test::ScratchDir("mask_class_id");
  {
    DetectionsWriter w(dir, "test", "");
    FrameDetections f;
    f.stamp_text = "1.0";
    DetectedInstance d;
    d.id = 1, d.class_id = 0, d.class_name = "person", d.confidence = 0.9;
    d.x_min = 1, d.y_min = 1, d.x_max = 5, d.y_max = 5;
    f.instances.push_back(d);
    w.Write(f);
    w.Finish();
  }
  // Edit the record as a hand-made file would: class 999.
  const std::string txt = dir + "/1.0.txt";
  std::string s = test::ReadFileBytes(txt);
  const size_t at = s.find("1 0 person");
  REQUIRE(at != std::string::npos);
  s.replace(at, 10, "1 999 person");
  WriteText(txt, s);
  DetectionsReader r(dir);
  try {
    r.Read("1.0", cv::Size(10, 10));
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("class_id must be -1 (unknown) or a COCO id 0..79, got 999") != std::string::npos);
    CHECK(e.line() > 0);
  }
}

TEST_CASE("mask format: a stamp in index.txt that is not a number is named (issue 20 item 10)") {
  const std::string dir = test::ScratchDir("mask_bad_stamp");
  {
    DetectionsWriter w(dir, "test", "");
    FrameDetections f;
    f.stamp_text = "1.0";
    w.Write(f);
    w.Finish();
  }
  std::string index = test::ReadFileBytes(dir + "/index.txt");
  const size_t at = index.find("1.0 ");
  REQUIRE(at != std::string::npos);
  index.replace(at, 3, "1.o");
  WriteText(dir + "/index.txt", index);
  try {
    DetectionsReader r(dir);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("stamp '1.o' is not a number") != std::string::npos);
    CHECK(e.line() > 0);
  }
}
