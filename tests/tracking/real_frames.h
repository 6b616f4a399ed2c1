// Frames of the bundled real TUM fr1_desk clip (datasets/real/tum_fr1_desk_9frames) prepared as
// the pipeline prepares them (grey = luminance, ORB, undistorted keys, depth per key), for the
// tracking and mapping unit tests.
#pragma once
#include <opencv2/imgproc.hpp>

#include "features/orb_extractor.h"
#include "io/sequence.h"
#include "map/frame.h"
#include "test_support.h"

namespace dynref::test {

inline Sequence Fr1Desk() { return OpenSequence(SourcePath("datasets/real/tum_fr1_desk_9frames")); }

// Image `image` of seq as a frame with index `index` and the image's own stamp.
inline Frame LoadRealFrame(const Sequence& seq, int image, features::OrbExtractor& extractor, int index = -1) {
  Frame f;
  f.index = index < 0 ? image : index;
  f.stamp = seq.frames[image].rgb_stamp;
  f.rgb = LoadRgb(seq, seq.frames[image]);
  f.depth_m = LoadDepthMeters(seq, seq.frames[image]);
  cv::cvtColor(f.rgb, f.grey, cv::COLOR_BGR2GRAY);
  extractor.Extract(f.grey, &f.keys, &f.descriptors);
  f.pyramid = ScalePyramid::Make(8, 1.2);
  f.FinishFeatures(seq.camera);
  return f;
}

}  // namespace dynref::test
