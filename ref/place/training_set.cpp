// Training descriptors from sequences (see training_set.h).
#include "place/training_set.h"

#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "features/orb_extractor.h"
#include "io/sequence.h"

namespace dynref::place {

void TrainingSetOptions::Check() const {
  if (sequences.empty()) throw InputError("--sequence", "give at least one sequence folder");
  if (every < 1) throw InputError("--every", "must be >= 1, got " + std::to_string(every));
  if (max_frames < 0) throw InputError("--max-frames", "must be >= 0, got " + std::to_string(max_frames));
  if (n_features < 1 || n_features > 100000)
    throw InputError("--features", "must be in 1..100000, got " + std::to_string(n_features));
}

TrainingSet ExtractTrainingSet(const TrainingSetOptions& options,
                               const std::function<void(const std::string&)>& progress) {
  options.Check();
  features::OrbOptions orb;
  orb.n_features = options.n_features;
  orb.Check();
  features::OrbExtractor extractor(orb);
  TrainingSet set;
  SequenceOptions so;
  so.camera = options.camera;
  for (const std::string& root : options.sequences) {
    const Sequence seq = OpenSequence(root, so);
    int used = 0;
    for (size_t i = 0; i < seq.frames.size(); i += static_cast<size_t>(options.every)) {
      if (options.max_frames > 0 && used >= options.max_frames) break;
      const cv::Mat rgb = LoadRgb(seq, seq.frames[i]);
      cv::Mat grey;
      cv::cvtColor(rgb, grey, options.rgb_flag ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
      std::vector<cv::KeyPoint> keys;
      cv::Mat desc;
      extractor.Extract(grey, &keys, &desc);
      set.images.push_back(DescriptorRows(desc, "ORB extractor"));
      set.descriptors += set.images.back().size();
      set.sources.push_back(root + "#" + std::to_string(seq.frames[i].index));
      ++used;
    }
    if (progress)
      progress(root + ": " + std::to_string(used) + " frames, " + std::to_string(set.descriptors) +
               " descriptors so far");
  }
  return set;
}

}  // namespace dynref::place
