// Training descriptors from sequence folders (`dynref vocab train`): every `every`-th frame of each
// sequence, in the order given, converted to grey as the backbone does (camera_rgb_flag true:
// cv::imread's BGR image through COLOR_RGB2GRAY, as ORB-SLAM2 with Camera.RGB: 1) and passed
// through the backbone's ORB extractor (features::OrbExtractor with `n_features`, ORB-SLAM2's
// other defaults). One training image = one frame.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "place/vocabulary.h"

namespace dynref::place {

struct TrainingSetOptions {
  std::vector<std::string> sequences;  // TUM-layout folders (dynref synth output, TUM, Bonn)
  std::string camera;                  // SequenceOptions::camera ("" = auto)
  int every = 1;                       // frame stride
  int max_frames = 0;                  // per sequence, 0 = all
  int n_features = 1000;               // ORB features per frame
  bool rgb_flag = true;                // backbone camera_rgb_flag
  void Check() const;                  // InputError naming the bad option
};

struct TrainingSet {
  std::vector<std::vector<Descriptor>> images;
  std::vector<std::string> sources;  // "<sequence>#<frame index>" per image
  size_t descriptors = 0;
};

TrainingSet ExtractTrainingSet(const TrainingSetOptions& options,
                               const std::function<void(const std::string&)>& progress = {});

}  // namespace dynref::place
