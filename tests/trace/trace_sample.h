// Hand-made traces for the trace tests: a few frames with every record type.
#pragma once
#include <string>

#include "trace/trace_writer.h"

namespace dynref::test {

struct SampleTweak {
  double after_delta = 0;       // added to the "after" of mp7 in frame 1, stage mgd.temporal
  bool drop_decision = false;   // omit the decision on f1.2 in frame 1
  bool extra_decision = false;  // add a decision on f1.9 in frame 1
  bool reverse_frame1 = false;  // write frame 1's probability updates in reverse order
};

inline void WriteSampleTrace(const std::string& path, const SampleTweak& tweak = {}) {
  using namespace dynref::trace;
  RunHeader h;
  h.dynref_version = "0.1.0";
  h.dynref_commit = "test";
  h.method = "sample";
  h.config_json = "{\"a\":1}";
  h.sequence_path = "/data/seq";
  h.input_hashes = {{"rgb.txt", "abc"}};
  h.detector_source = "none";
  TraceWriter w(path, Level::kFull, h);
  for (int frame = 0; frame < 3; ++frame) {
    w.BeginFrame(frame, 1305031102.175304 + 0.033 * frame);
    SE3 T = SE3::Identity();
    T.translation() = Eigen::Vector3d(0.1 * frame, 1.0 / 3.0, -2.5);
    w.FramePose("initial", T);
    w.FrameCount("extract", "keypoints", 1000 + frame);
    // Feature 2 is the suppressed one (the sgdo.epipolar decision below): no final map point, but
    // associated with mp20 when the stages saw it (schema 3 associated_map_point_id).
    for (int i = 0; i < 4; ++i)
      w.Observation(i, i % 2 ? 7 + i : -1, i % 2 ? 7 + i : (i == 2 ? 20 : -1), 100.25 + i, 200.5 / 3.0 + i,
                    i ? 1.5 + 0.1 * i : 0.0, i % 3, 0x1234567890abcdefULL + i);
    auto prob = [&](const std::string& entity, double after) {
      double a = after;
      if (frame == 1 && entity == "mp7") a += tweak.after_delta;
      w.ProbabilityUpdate("mgd.temporal", EntityKind::kMapPoint, entity,
                          {{"d_px", 0.1 * frame + 0.7}, {"n_obs", 3}}, 0.5, a);
    };
    if (frame == 1 && tweak.reverse_frame1) {
      prob("mp9", 0.125);
      prob("mp7", 0.8 / 3.0);
    } else {
      prob("mp7", 0.8 / 3.0 + 0.01 * frame);
      prob("mp9", 0.125);
    }
    w.Residual("track.pose#1", "rgbd3", "mp7@f" + std::to_string(frame), {0.5, -0.25, 1e-3},
               {0.01, -0.02, 1e-5}, 1.0, 0.9, 0.0123, 0.000625, true);
    if (!(frame == 1 && tweak.drop_decision))
      w.Decision("sgdo.epipolar", EntityKind::kFeature, "f" + std::to_string(frame) + ".2", false,
                 "epipolar distance 3.2 px > 1 px");
    if (frame == 1 && tweak.extra_decision)
      w.Decision("sgdo.epipolar", EntityKind::kFeature, "f1.9", true, "inlier");
    SE3 T2 = T;
    T2.translation().x() += 1e-3;
    w.FramePose("final", T2);
  }
  w.Close("complete");
}

}  // namespace dynref::test
