// A tiny hand-made run for the render tests: a 2-frame 640x480 sequence folder (rgb/depth PNGs,
// rgb.txt/depth.txt, camera.yaml), GT (SEQ/gt via DetectionsWriter + moving.txt), a detections
// folder, and RUN/{trace.dtr, run.json} with features, probabilities, decisions, a line sample,
// a plane region and an instance-mask update.
#pragma once
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/atomic_file.h"
#include "io/camera.h"
#include "io/mask_format.h"
#include "trace/trace_writer.h"
#include "io/image_file.h"

namespace dynref::test {

struct SyntheticRun {
  std::string sequence, run;
};

inline SyntheticRun MakeSyntheticRun(const std::string& dir) {
  SyntheticRun out{dir + "/seq", dir + "/run"};
  const std::string seq = out.sequence;
  std::system(("mkdir -p '" + seq + "/rgb' '" + seq + "/depth' '" + out.run + "'").c_str());
  WriteOrbSlamCameraYaml(CameraPreset("synthetic"), seq + "/camera.yaml");
  const char* stamps[2] = {"1.000000", "1.033333"};
  std::string rgb_txt = "# color images\n# file: synthetic\n# timestamp filename\n";
  std::string depth_txt = "# depth maps\n# file: synthetic\n# timestamp filename\n";
  DetectionsWriter gt(seq + "/gt", "synthetic-gt", "");
  DetectionsWriter det(seq + "/det", "test-detector", "");
  std::string moving;
  for (int f = 0; f < 2; ++f) {
    // Background: smooth deterministic gradient; a "person" block and a "chair" block.
    cv::Mat bgr(480, 640, CV_8UC3);
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 640; ++x)
        bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>(60 + x / 8), static_cast<uchar>(70 + y / 6),
                                            static_cast<uchar>(90 + (x + y) / 16));
    const int px = 200 + 12 * f;
    cv::rectangle(bgr, cv::Rect(px, 120, 120, 280), cv::Scalar(40, 40, 160), cv::FILLED);
    cv::rectangle(bgr, cv::Rect(420, 300, 100, 120), cv::Scalar(30, 110, 60), cv::FILLED);
    dynref::ImageWrite(seq + "/rgb/" + stamps[f] + ".png", bgr);
    cv::Mat depth(480, 640, CV_16U, cv::Scalar(5000));
    dynref::ImageWrite(seq + "/depth/" + stamps[f] + ".png", depth);
    rgb_txt += std::string(stamps[f]) + " rgb/" + stamps[f] + ".png\n";
    depth_txt += std::string(stamps[f]) + " depth/" + stamps[f] + ".png\n";
    // Ground truth: instance 1 (person) moves, instance 2 (chair) is static.
    FrameDetections g;
    g.stamp_text = stamps[f];
    g.instance_ids = cv::Mat(480, 640, CV_16U, cv::Scalar(0));
    g.instance_ids(cv::Rect(px, 120, 120, 280)).setTo(1);
    g.instance_ids(cv::Rect(420, 300, 100, 120)).setTo(2);
    DetectedInstance person{1, 0, "person", 1.0, double(px), 120, double(px + 119), 399, true};
    DetectedInstance chair{2, 56, "chair", 1.0, 420, 300, 519, 419, true};
    g.instances = {person, chair};
    gt.Write(g);
    moving += std::string(stamps[f]) + " 1\n";
    // Detector: person mask slightly too small, chair box only.
    FrameDetections d;
    d.stamp_text = stamps[f];
    d.instance_ids = cv::Mat(480, 640, CV_16U, cv::Scalar(0));
    d.instance_ids(cv::Rect(px + 6, 130, 100, 250)).setTo(1);
    d.instances = {{1, 0, "person", 0.87, double(px + 6), 130, double(px + 105), 379, true},
                   {2, 56, "chair", 0.61, 416, 296, 524, 424, false}};
    det.Write(d);
  }
  gt.Finish();
  det.Finish();
  AtomicWriteFile(seq + "/gt/moving.txt", moving);
  AtomicWriteFile(seq + "/rgb.txt", rgb_txt);
  AtomicWriteFile(seq + "/depth.txt", depth_txt);
  AtomicWriteFile(out.run + "/run.json", "{\n  \"sequence\": \"" + seq + "\",\n  \"method\": \"test\",\n"
                                         "  \"detections\": \"" + seq + "/det\"\n}\n");
  // Trace: a grid of features; those on the person get high probability (most rejected), one
  // person feature is missed (FN) and one background feature is rejected (FP).
  using namespace dynref::trace;
  RunHeader h;
  h.method = "test";
  h.sequence_path = seq;
  h.detections_dir = seq + "/det";
  TraceWriter w(out.run + "/trace.dtr", Level::kFull, h);
  for (int f = 0; f < 2; ++f) {
    w.BeginFrame(f, f == 0 ? 1.0 : 1.033333);
    w.FrameCount("extract", "keypoints", 48);
    w.FrameCount("sgdo.epipolar", "rejected", 9);
    int idx = 0, person_seen = 0;
    for (int gy = 0; gy < 6; ++gy)
      for (int gx = 0; gx < 8; ++gx, ++idx) {
        const double u = 40 + gx * 78 + 3.25 * f, v = 40 + gy * 78 + 0.5;
        const bool on_person = u >= 200 + 12 * f && u < 320 + 12 * f && v >= 120 && v < 400;
        const int mp = idx < 40 ? 100 + idx : -1;  // the last row is unmatched
        w.Observation(idx, mp, u, v, 1.0, idx % 4, 0x9e3779b97f4a7c15ULL * (idx + 1));
        const std::string fid = "f" + std::to_string(f) + "." + std::to_string(idx);
        double p = 0.05 + 0.2 * ((idx * 7) % 5) / 4.0;
        if (on_person) p = 0.7 + 0.05 * (person_seen++ % 6);
        if (idx == 45) continue;  // no probability traced: grey dot
        w.ProbabilityUpdate("mgd.temporal", EntityKind::kFeature, fid, {{"d_px", 1.5}}, 0.5, p);
        const bool fn = on_person && person_seen == 1;  // missed dynamic feature
        const bool fp = idx == 3;                       // static feature wrongly rejected
        if (idx % 3 == 2) continue;  // undecided
        const bool kept = fp ? false : fn ? true : !on_person;
        w.Decision("sgdo.epipolar", EntityKind::kFeature, fid, kept, kept ? "inlier" : "dynamic");
      }
    w.ProbabilityUpdate("lines.check", EntityKind::kLineSample, "l" + std::to_string(f) + ".0",
                        {{"x0", 60}, {"y0", 440}, {"x1", 380}, {"y1", 455}}, 0.5, 0.15);
    w.ProbabilityUpdate("lines.check", EntityKind::kLineSample, "l" + std::to_string(f) + ".1",
                        {{"x0", 240}, {"y0", 140}, {"x1", 250}, {"y1", 380}}, 0.5, 0.9);
    w.Decision("lines.check", EntityKind::kLineSample, "l" + std::to_string(f) + ".1", false, "dynamic");
    w.ProbabilityUpdate("planes.check", EntityKind::kPlane, "pl" + std::to_string(f) + ".0",
                        {{"x_min", 360}, {"y_min", 40}, {"x_max", 620}, {"y_max", 200}}, 0.5, 0.3);
    w.ProbabilityUpdate("mask.check", EntityKind::kInstanceMask, "i" + std::to_string(f) + ".1", {},
                        0.5, 0.93);
    w.Decision("mask.check", EntityKind::kInstanceMask, "i" + std::to_string(f) + ".1", false, "moving");
  }
  w.Close("complete");
  return out;
}

}  // namespace dynref::test
