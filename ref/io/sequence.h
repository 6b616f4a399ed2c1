// TUM RGB-D / Bonn RGB-D sequence folders: rgb.txt, depth.txt, optional groundtruth.txt and
// association file; association as TUM's associate.py (greedy one-to-one, smallest |dt| first,
// max_difference 0.02 s, no offset).
#pragma once
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/se3.h"
#include "io/camera.h"

namespace dynref {

struct FrameEntry {
  int index = 0;                 // 0-based position among associated pairs (rgb-time order)
  double rgb_stamp = 0;
  std::string rgb_stamp_text;    // exactly as written in rgb.txt (used as key for detections)
  std::string rgb_path;          // absolute or root-relative resolved path
  double depth_stamp = 0;
  std::string depth_path;
  // Source of each entry for error messages: list file (rgb.txt, depth.txt or the association
  // file) and its 1-based line.
  std::string rgb_list_file, depth_list_file;
  int rgb_line = 0, depth_line = 0;
};

struct SequenceOptions {
  double max_difference_s = 0.02;
  // Camera: preset name, path to an ORB-SLAM2 YAML, or empty = auto (camera.yaml in the folder,
  // else a preset guessed from the folder name: freiburg1/2/3, bonn); no guess is an error.
  std::string camera;
  // Optional association file (TUM associate.py output); empty = associate rgb.txt/depth.txt.
  std::string association_file;
};

struct Sequence {
  std::string root;
  Camera camera;
  std::vector<FrameEntry> frames;          // associated pairs, ascending rgb time
  std::vector<StampedPose> groundtruth;    // T_wc, may be empty
  size_t rgb_count = 0, depth_count = 0;   // entries in rgb.txt / depth.txt (association file rows)
  // How the camera was chosen, e.g. "preset tum_fr1 (folder name)", "camera.yaml in the folder".
  std::string camera_source;
  std::string association_source;          // "associate.py greedy, max_difference 0.02 s" or file
  std::string groundtruth_path;            // empty when the folder has no groundtruth.txt
  int groundtruth_duplicates_dropped = 0;  // equal consecutive GT stamps (later line kept, as TUM)
};

// InputError (file, line) for: missing folder or list file, malformed/non-numeric/non-increasing
// lines, an associated image that does not exist, zero associated pairs, a bad ground truth,
// or RGB and depth of the first pair differing in size from each other or from the camera.
Sequence OpenSequence(const std::string& root, const SequenceOptions& options = {});
// Resolves SequenceOptions::camera for the folder (preset name, YAML path, or auto); sets
// *source to how it was chosen.
Camera ResolveSequenceCamera(const std::string& root, const std::string& camera,
                             std::string* source);
// CV_8UC3 BGR; InputError if unreadable or not camera-sized.
cv::Mat LoadRgb(const Sequence& seq, const FrameEntry& frame);
// CV_32F metres (0 = no depth); InputError if unreadable, not 16-bit, or not camera-sized.
cv::Mat LoadDepthMeters(const Sequence& seq, const FrameEntry& frame);

}  // namespace dynref
