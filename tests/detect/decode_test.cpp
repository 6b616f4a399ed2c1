// Decoding unit tests on hand-made tensors: NanoDet GFL head, per-class NMS, YOLOv8/11 boxes
// (both output orientations, letterbox) and YOLO-seg prototype masks.
#include <catch2/catch.hpp>
#include <opencv2/core.hpp>

#include "detect/candidates.h"
#include "detect/nanodet_decode.h"
#include "detect/yolo_decode.h"

using namespace dynref::detect;

namespace {

// Logits with a sharp peak at bin k (softmax weight ~1 - 1e-8 at k).
void PeakBins(float* b, int bins, int k) {
  for (int i = 0; i < bins; ++i) b[i] = (i == k) ? 20.f : 0.f;
}

std::vector<NanodetLevel> EmptyNanodet() {
  std::vector<NanodetLevel> levels;
  for (int s : {8, 16, 32}) {
    const int n = 416 / s;
    levels.push_back({s, cv::Mat::zeros(n * n, 80, CV_32F), cv::Mat::zeros(n * n, 44, CV_32F)});
  }
  return levels;
}

Candidate Cand(int cls, double score, double x0, double y0, double x1, double y1, int anchor) {
  Candidate c;
  c.class_id = cls;
  c.score = score;
  c.x_min = x0;
  c.y_min = y0;
  c.x_max = x1;
  c.y_max = y1;
  c.anchor = anchor;
  return c;
}

}  // namespace

TEST_CASE("decode: distribution expectation of GFL bins") {
  float flat[11] = {0};
  CHECK(DistributionExpectation(flat, 11) == Approx(5.0).margin(1e-12));
  float peak[11];
  PeakBins(peak, 11, 3);
  CHECK(DistributionExpectation(peak, 11) == Approx(3.0).margin(1e-6));
  float two[11] = {0};
  two[2] = two[4] = 30.f;  // equal mass on 2 and 4 -> 3, and no overflow at large logits
  CHECK(DistributionExpectation(two, 11) == Approx(3.0).margin(1e-6));
}

TEST_CASE("decode: NanoDet cell centre, side distances and image scaling") {
  auto levels = EmptyNanodet();
  const int row = 10, col = 20, i = row * 52 + col;  // stride 8 level: 52 x 52 cells
  levels[0].scores.at<float>(i, 0) = 0.9f;
  levels[0].scores.at<float>(i, 5) = 0.4f;
  float* b = levels[0].boxes.ptr<float>(i);
  PeakBins(b, 11, 2);       // left 2 * 8 = 16
  PeakBins(b + 11, 11, 3);  // top 24
  PeakBins(b + 22, 11, 4);  // right 32
  PeakBins(b + 33, 11, 5);  // bottom 40
  // A second cell below threshold on the stride-32 level.
  levels[2].scores.at<float>(7, 3) = 0.2f;
  NanodetDecodeOptions o;
  o.image_width = 832;  // x scaled by 2
  o.image_height = 416;
  o.score_threshold = 0.3;
  const auto c = DecodeNanodet(levels, o);
  REQUIRE(c.size() == 1);
  CHECK(c[0].class_id == 0);
  CHECK(c[0].score == Approx(0.9));
  CHECK(c[0].anchor == i);
  // Centre (20.5 * 8, 10.5 * 8) = (164, 84) in 416 units.
  CHECK(c[0].x_min == Approx((164 - 16) * 2.0).margin(1e-5));
  CHECK(c[0].y_min == Approx(84 - 24).margin(1e-5));
  CHECK(c[0].x_max == Approx((164 + 32) * 2.0).margin(1e-5));
  CHECK(c[0].y_max == Approx(84 + 40).margin(1e-5));
  // The README's centre convention (offset 0) moves the box by half a stride.
  o.cell_offset = 0;
  CHECK(DecodeNanodet(levels, o)[0].x_min == Approx((160 - 16) * 2.0).margin(1e-5));
}

TEST_CASE("decode: NanoDet anchors count across levels and boxes are clipped") {
  auto levels = EmptyNanodet();
  levels[1].scores.at<float>(0, 62) = 0.7f;  // stride 16, top-left cell, tvmonitor
  PeakBins(levels[1].boxes.ptr<float>(0), 44, 10);  // left 10 bins -> 160 px, clipped to 0
  NanodetDecodeOptions o;
  const auto c = DecodeNanodet(levels, o);
  REQUIRE(c.size() == 1);
  CHECK(c[0].class_id == 62);
  CHECK(c[0].anchor == 52 * 52);
  CHECK(c[0].x_min == 0.0);
}

TEST_CASE("decode: NanoDet rejects tensors of the wrong shape") {
  auto levels = EmptyNanodet();
  levels[2].boxes = cv::Mat::zeros(169, 32, CV_32F);  // 8 bins per side instead of 11
  CHECK_THROWS_AS(DecodeNanodet(levels, NanodetDecodeOptions{}), std::invalid_argument);
}

TEST_CASE("decode: per-class NMS is greedy per class and order independent") {
  std::vector<Candidate> in = {
      Cand(0, 0.8, 0, 0, 100, 100, 4),     // kept
      Cand(0, 0.7, 10, 10, 110, 110, 2),   // IoU 0.68 with the first: suppressed
      Cand(56, 0.6, 10, 10, 110, 110, 3),  // other class: kept
      Cand(0, 0.5, 200, 200, 250, 250, 1), // far away: kept
      Cand(0, 0.8, 5, 0, 105, 100, 7),     // same score as anchor 4, higher anchor: suppressed
  };
  const auto out = PerClassNms(in, 0.5, 100);
  REQUIRE(out.size() == 3);
  CHECK(out[0].anchor == 4);
  CHECK(out[1].anchor == 3);
  CHECK(out[2].anchor == 1);
  std::vector<Candidate> reversed(in.rbegin(), in.rend());
  const auto out2 = PerClassNms(reversed, 0.5, 100);
  REQUIRE(out2.size() == out.size());
  for (size_t i = 0; i < out.size(); ++i) CHECK(out2[i].anchor == out[i].anchor);
  CHECK(PerClassNms(in, 0.5, 2).size() == 2);
  CHECK(BoxIou(in[0], in[1]) == Approx(8100.0 / 11900.0));
}

TEST_CASE("decode: YOLO letterbox and boxes in both output orientations") {
  const Letterbox lb = ComputeLetterbox(1280, 720, 640);
  CHECK(lb.scale == Approx(0.5));
  CHECK(lb.scaled_width == 640);
  CHECK(lb.scaled_height == 360);
  CHECK(lb.pad_left == 0);
  CHECK(lb.pad_top == 140);
  CHECK(YoloAnchorCount(640) == 8400);

  const int nc = 80, anchors = 8400;
  int sizes[3] = {1, 4 + nc, anchors};
  cv::Mat out(3, sizes, CV_32F, cv::Scalar(0));
  cv::Mat view(4 + nc, anchors, CV_32F, out.data);
  view.at<float>(0, 5) = 320;  // cx
  view.at<float>(1, 5) = 320;  // cy
  view.at<float>(2, 5) = 100;  // w
  view.at<float>(3, 5) = 50;   // h
  view.at<float>(4 + 2, 5) = 0.8f;
  view.at<float>(4 + 7, 5) = 0.3f;
  view.at<float>(4 + 1, 99) = 0.1f;  // below threshold
  const auto check = [&](const cv::Mat& blob) {
    const YoloPredictions p = ArrangeYoloPredictions(blob, 640, 0);
    CHECK(p.num_classes == 80);
    const auto c = DecodeYoloBoxes(p, lb, 0.25);
    REQUIRE(c.size() == 1);
    CHECK(c[0].class_id == 2);
    CHECK(c[0].anchor == 5);
    CHECK(c[0].x_min == Approx((320 - 50) / 0.5));
    CHECK(c[0].y_min == Approx((320 - 25 - 140) / 0.5));
    CHECK(c[0].x_max == Approx((320 + 50) / 0.5));
    CHECK(c[0].y_max == Approx((320 + 25 - 140) / 0.5));
  };
  check(out);
  int tsizes[3] = {1, anchors, 4 + nc};
  cv::Mat transposed(3, tsizes, CV_32F);
  cv::Mat tview(anchors, 4 + nc, CV_32F, transposed.data);
  cv::transpose(view, tview);
  check(transposed);
  // 84 channels cannot hold 80 classes plus 32 mask coefficients; no anchor dimension at 320.
  CHECK_THROWS_AS(ArrangeYoloPredictions(out, 640, 82), std::invalid_argument);
  CHECK_THROWS_AS(ArrangeYoloPredictions(out, 320, 0), std::invalid_argument);
}

TEST_CASE("decode: YOLO-seg mask = sigmoid(coefficients . prototypes), cropped to the box") {
  const int nm = 2, nc = 1, anchors = YoloAnchorCount(640);
  cv::Mat pred = cv::Mat::zeros(4 + nc + nm, anchors, CV_32F);
  // Anchor 0: coefficients (1, 0); anchor 1: (-1, 0).
  pred.at<float>(4 + nc, 0) = 1.f;
  pred.at<float>(4 + nc, 1) = -1.f;
  YoloPredictions p;
  p.channels_by_anchor = pred;
  p.num_classes = nc;
  p.num_mask_coeffs = nm;
  int psizes[4] = {1, nm, 160, 160};
  cv::Mat protos(4, psizes, CV_32F, cv::Scalar(0));
  cv::Mat proto0(160, 160, CV_32F, protos.data);
  proto0.setTo(-10.f);
  proto0(cv::Rect(40, 40, 80, 40)).setTo(10.f);  // x 40..119, y 40..79 in prototype pixels
  const Letterbox lb = ComputeLetterbox(640, 640, 640);  // prototypes are 1/4 of the image
  const Candidate box = Cand(0, 0.9, 100, 100, 600, 400, 0);
  const cv::Mat m = DecodeYoloMask(p, protos, box, lb);
  REQUIRE(m.type() == CV_8U);
  REQUIRE(m.size() == cv::Size(640, 640));
  CHECK(m.at<uchar>(240, 300) == 255);
  CHECK(m.at<uchar>(240, 130) == 0);
  CHECK(m.at<uchar>(350, 300) == 0);
  CHECK(std::abs(cv::countNonZero(m) - 320 * 160) < 0.05 * 320 * 160);
  // Cropped to the box: nothing right of x = 300 for a narrower box.
  const cv::Mat narrow = DecodeYoloMask(p, protos, Cand(0, 0.9, 0, 0, 300, 640, 0), lb);
  CHECK(cv::countNonZero(narrow(cv::Rect(300, 0, 340, 640))) == 0);
  CHECK(cv::countNonZero(narrow) > 0);
  // Negative coefficient: the region is off, the rest of the box on.
  const cv::Mat inverse = DecodeYoloMask(p, protos, Cand(0, 0.9, 100, 100, 600, 400, 1), lb);
  CHECK(inverse.at<uchar>(240, 300) == 0);
  CHECK(inverse.at<uchar>(380, 500) == 255);
  CHECK(inverse.at<uchar>(450, 500) == 0);  // outside the box
}
