// A hand-written trace for `trace feature --follow` (ref/trace/README.md "Following a feature"):
//   feature chain  f0.10 - f1.11 - f2.12 - f3.13 - f4.14   (mgd.inherit prev_index, frames 0..4)
//                  f2.12 and f5.15 both associated with mp50 (OBS); f5.15 is suppressed (map_point_id
//                  -1, associated 50, DECISION kept 0); f6.16 - f5.15 (prev_index); residual mp50@f2
//   distractors    f3.1 - f2.0 (prev_index) with map_point input 60; f1.99 never associated;
//                  f1.50 names f0.10 as its previous feature too (a sibling of f1.11)
//   line samples   l0.0 - l1.0 (prev_index), l1.0 and l3.2 name map line ml3 (map_line input)
//   masks          i0.2, i1.2, i3.2 (instance 2), i1.5 (instance 5)
//   residual links kf3 = frame 1; mp70@kf3 and mp70@f6 with input feature 99: f1.99 - mp70 - f6.99
//   two landmarks  f3.70 - mp90 - f5.70 - mp91 - f6.71 (map_point inputs): from f3.70, mp91 is a
//                  landmark of an entity mp90 brought in, so it joins without bringing in f6.71
#pragma once
#include <string>

#include "trace/trace_writer.h"

namespace dynref::test {

inline void WriteFollowTrace(const std::string& path) {
  using namespace dynref::trace;
  TraceWriter w(path, Level::kFull, RunHeader{});
  const auto fid = [](int frame, int i) { return "f" + std::to_string(frame) + "." + std::to_string(i); };
  for (int frame = 0; frame < 7; ++frame) {
    w.BeginFrame(frame, 10.0 + 0.1 * frame);
    w.FrameCount("extract", "keypoints", 100);
    const int a = 10 + frame;  // the chain's feature index in this frame
    const int64_t mp = frame == 2 ? 50 : -1, associated = frame == 2 || frame == 5 ? 50 : -1;
    w.Observation(a, mp, associated, 5.0 * frame, 7.0, 1.5, 0, 0xABCull + a);
    w.Observation(99, -1, -1, 1.0, 1.0, 0.0, 0, 0x99ull);
    const int prev = frame == 0 || frame == 5 ? -1 : a - 1;  // the chain breaks at frame 5
    const double p = 0.1 * frame;
    w.ProbabilityUpdate("mgd.inherit", EntityKind::kFeature, fid(frame, a),
                        {{"source", prev >= 0 ? 0.0 : 2.0}, {"prev_index", double(prev)}, {"map_point", double(mp)}}, p, p);
    w.ProbabilityUpdate("mgd.smooth", EntityKind::kFeature, fid(frame, a), {{"S", 0.5}}, p, p + 0.05);
    if (frame == 5) w.Decision("mgd.probability", EntityKind::kFeature, fid(frame, a), false, "p>tau_dyn");
    if (frame == 2)
      w.Residual("track.pose#1", "rgbd3", "mp50@f2", {0.1, 0.2, 0.3}, {0.01, 0.02, 0.03}, 1.0, 1.0, 0.0014, 0.0014, true);
    if (frame == 3)
      w.ProbabilityUpdate("mgd.inherit", EntityKind::kFeature, "f3.1",
                          {{"source", 0.0}, {"prev_index", 0.0}, {"map_point", 60.0}}, 0.9, 0.9);
    if (frame == 2) w.ProbabilityUpdate("mgd.smooth", EntityKind::kFeature, "f2.0", {{"S", 1.0}}, 0.9, 0.95);
    if (frame <= 1)
      w.ProbabilityUpdate("mgd.inherit", EntityKind::kLineSample, "l" + std::to_string(frame) + ".0",
                          {{"sample", 0.0}, {"prev_index", frame == 1 ? 0.0 : -1.0}, {"map_line", frame == 1 ? 3.0 : -1.0}},
                          0.2, 0.2);
    if (frame == 3)
      w.ProbabilityUpdate(kGeometryStage, EntityKind::kLineSample, "l3.2", {{"map_line", 3.0}}, 0.0, 0.0);
    if (frame == 0 || frame == 1 || frame == 3)
      w.ProbabilityUpdate("sgdo.vote", EntityKind::kInstanceMask, "i" + std::to_string(frame) + ".2",
                          {{"moving", 1.0}}, 0.0, 1.0);
    if (frame == 1) w.Decision("sgdo.vote", EntityKind::kInstanceMask, "i1.5", true, "still");
    // Residual links (the backbone's track.keyframe / localba.obs / track.pose.obs records):
    // kf3 is frame 1, and mp70 is observed by f1.99 (through kf3) and f6.99.
    if (frame == 1) w.ProbabilityUpdate("track.keyframe", EntityKind::kKeyFrame, "kf3", {{"frame", 1.0}}, 0.0, 0.0);
    if (frame == 6) {
      w.ProbabilityUpdate("localba.obs", EntityKind::kFeature, "mp70@kf3", {{"feature", 99.0}}, 0.0, 0.0);
      w.ProbabilityUpdate("track.pose.obs", EntityKind::kFeature, "mp70@f6", {{"feature", 99.0}}, 0.0, 0.0);
    }
    if (frame == 3 || frame == 5)  // f3.70 and f5.70 on mp90, f5.70 (another stage) and f6.71 on mp91
      w.ProbabilityUpdate("mgd.inherit", EntityKind::kFeature, fid(frame, 70),
                          {{"source", 2.0}, {"prev_index", -1.0}, {"map_point", 90.0}}, 0.0, 0.0);
    if (frame == 5 || frame == 6)
      w.ProbabilityUpdate("match.mnn2", EntityKind::kFeature, fid(frame, frame == 5 ? 70 : 71), {{"map_point", 91.0}}, 0.0, 0.0);
    if (frame == 1)  // a sibling of f1.11: another feature naming f0.10 as its previous feature
      w.ProbabilityUpdate("mgd.inherit", EntityKind::kFeature, "f1.50",
                          {{"source", 0.0}, {"prev_index", 10.0}, {"map_point", -1.0}}, 0.0, 0.0);
  }
  w.Close("complete");
}

}  // namespace dynref::test
