#include "io/sequence.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/format.h"
#include "io/association.h"
#include "io/stamped_list.h"
#include "io/trajectory.h"
#include "io/image_file.h"

namespace dynref {
namespace {

bool IsDir(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}
bool IsFile(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
// A --camera argument that names a file (FILE.yaml, FILE.yml or a path with '/') is read as one
// even when it does not exist, so the error says the file is missing, not "unknown preset".
bool LooksLikeCameraFile(const std::string& arg) {
  auto ends_with = [&](const std::string& suffix) {
    return arg.size() >= suffix.size() &&
           arg.compare(arg.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  return ends_with(".yaml") || ends_with(".yml") || arg.find('/') != std::string::npos;
}
std::string Join(const std::string& root, const std::string& rel) {
  if (!rel.empty() && rel[0] == '/') return rel;
  return root + "/" + rel;
}
std::string LastComponent(std::string p) {
  // "." or "seq/.." name no sequence: use the resolved path.
  if (char* real = ::realpath(p.c_str(), nullptr)) {
    p = real;
    std::free(real);
  }
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  const size_t slash = p.find_last_of('/');
  return slash == std::string::npos ? p : p.substr(slash + 1);
}
// True when `token` occurs in `name` delimited by non-alphanumerics (or the ends).
bool HasToken(const std::string& name, const std::string& token) {
  for (size_t pos = name.find(token); pos != std::string::npos; pos = name.find(token, pos + 1)) {
    const bool left = pos == 0 || !std::isalnum(static_cast<unsigned char>(name[pos - 1]));
    const size_t end = pos + token.size();
    const bool right = end == name.size() || !std::isalnum(static_cast<unsigned char>(name[end]));
    if (left && right) return true;
  }
  return false;
}

void CheckImageListed(const std::string& path, const std::string& list, int line,
                      const std::string& what) {
  if (!IsFile(path))
    throw InputError(list, line, what + " image listed but missing: " + path);
}

}  // namespace

Camera ResolveSequenceCamera(const std::string& root, const std::string& camera,
                             std::string* source) {
  std::string dummy;
  std::string& src = source ? *source : dummy;
  if (!camera.empty()) {
    if (IsCameraPresetName(camera)) {
      src = "preset " + camera + " (--camera)";
      return CameraPreset(camera);
    }
    if (IsFile(camera) || LooksLikeCameraFile(camera)) {
      src = "ORB-SLAM2 YAML " + camera + " (--camera)";
      return ReadOrbSlamCameraYaml(camera);
    }
    CameraPreset(camera);  // throws the "unknown preset" message listing the known ones
  }
  const std::string yaml = root + "/camera.yaml";
  if (IsFile(yaml)) {
    src = "camera.yaml in the folder";
    return ReadOrbSlamCameraYaml(yaml);
  }
  std::string name = LastComponent(root);
  for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const char* preset = nullptr;
  if (name.find("freiburg1") != std::string::npos || HasToken(name, "fr1")) preset = "tum_fr1";
  else if (name.find("freiburg2") != std::string::npos || HasToken(name, "fr2")) preset = "tum_fr2";
  else if (name.find("freiburg3") != std::string::npos || HasToken(name, "fr3")) preset = "tum_fr3";
  else if (name.find("bonn") != std::string::npos) preset = "bonn";
  if (!preset)
    throw InputError(root,
                     "cannot tell the camera: no camera.yaml in the folder and the folder name "
                     "names no freiburg1/2/3 or bonn sequence; pass --camera tum_fr1|tum_fr2|"
                     "tum_fr3|bonn|synthetic|FILE.yaml");
  src = std::string("preset ") + preset + " (guessed from the folder name)";
  return CameraPreset(preset);
}

namespace {

// Frames from an associate.py output: "rgb_stamp rgb_file depth_stamp depth_file".
void OpenSeqFromAssociationFile(const std::string& root, const std::string& association_file, Sequence* seq) {
  std::string assoc = association_file;
  if (assoc[0] != '/' && !IsFile(assoc)) assoc = Join(root, assoc);
  const std::vector<StampedLine> rows = ReadStampedList(assoc, 3, 3);
  for (const StampedLine& row : rows) {
    FrameEntry f;
    f.index = static_cast<int>(seq->frames.size());
    f.rgb_stamp = row.stamp;
    f.rgb_stamp_text = row.stamp_text;
    f.rgb_path = Join(root, row.fields[0]);
    f.depth_stamp = ParseNumberField(row.fields[1], assoc, row.line, "depth timestamp");
    if (!std::isfinite(f.depth_stamp))
      throw InputError(assoc, row.line, "depth timestamp '" + row.fields[1] + "' is not finite");
    f.depth_path = Join(root, row.fields[2]);
    f.rgb_list_file = f.depth_list_file = assoc;
    f.rgb_line = f.depth_line = row.line;
    seq->frames.push_back(std::move(f));
  }
  seq->rgb_count = seq->depth_count = rows.size();
  seq->association_source = "association file " + assoc;
}

// Frames from rgb.txt and depth.txt (associate.py rgb.txt depth.txt: first = rgb, second =
// depth, offset 0).
void OpenSeqFromTumLists(const std::string& root, double max_difference_s, Sequence* seq) {
  const std::string rgb_txt = root + "/rgb.txt", depth_txt = root + "/depth.txt";
  const std::vector<StampedLine> rgb = ReadStampedList(rgb_txt, 1, 1);
  const std::vector<StampedLine> depth = ReadStampedList(depth_txt, 1, 1);
  seq->rgb_count = rgb.size();
  seq->depth_count = depth.size();
  std::vector<double> rs, ds;
  for (const auto& r : rgb) rs.push_back(r.stamp);
  for (const auto& d : depth) ds.push_back(d.stamp);
  for (const StampMatch& m : AssociateTum(rs, ds, max_difference_s)) {
    FrameEntry f;
    f.index = static_cast<int>(seq->frames.size());
    f.rgb_stamp = rgb[m.first].stamp;
    f.rgb_stamp_text = rgb[m.first].stamp_text;
    f.rgb_path = Join(root, rgb[m.first].fields[0]);
    f.depth_stamp = depth[m.second].stamp;
    f.depth_path = Join(root, depth[m.second].fields[0]);
    f.rgb_list_file = rgb_txt;
    f.rgb_line = rgb[m.first].line;
    f.depth_list_file = depth_txt;
    f.depth_line = depth[m.second].line;
    seq->frames.push_back(std::move(f));
  }
  seq->association_source = "associate.py greedy one-to-one, max_difference " +
                            FormatDouble17(max_difference_s) + " s, offset 0";
  if (seq->frames.empty())
    throw InputError(rgb_txt, "zero associated RGB/depth pairs with " + depth_txt +
                                  " within " + FormatDouble17(max_difference_s) + " s");
}

// Sizes of the first pair (decoding every frame here would be slow; LoadRgb/LoadDepthMeters
// check each later frame against the camera size).
void OpenSeqCheckFirstPair(const Sequence& seq) {
  const FrameEntry& f = seq.frames.front();
  const cv::Mat rgb = dynref::ImageRead(f.rgb_path, cv::IMREAD_UNCHANGED);
  const cv::Mat depth = dynref::ImageRead(f.depth_path, cv::IMREAD_UNCHANGED);
  if (rgb.empty())
    throw InputError(f.rgb_list_file, f.rgb_line, "cannot decode RGB image " + f.rgb_path);
  if (depth.empty())
    throw InputError(f.depth_list_file, f.depth_line,
                     "cannot decode depth image " + f.depth_path);
  if (depth.depth() != CV_16U || depth.channels() != 1)
    throw InputError(f.depth_list_file, f.depth_line,
                     "depth image " + f.depth_path + " is not a 1-channel 16-bit PNG (" +
                         std::to_string(8 * static_cast<int>(depth.elemSize1())) + "-bit, " +
                         std::to_string(depth.channels()) + " channel(s))");
  if (rgb.size() != depth.size())
    throw InputError(f.depth_list_file, f.depth_line,
                     "image size mismatch: RGB " + f.rgb_path + " is " +
                         std::to_string(rgb.cols) + "x" + std::to_string(rgb.rows) +
                         ", depth " + f.depth_path + " is " + std::to_string(depth.cols) +
                         "x" + std::to_string(depth.rows));
  if (rgb.cols != seq.camera.width || rgb.rows != seq.camera.height)
    throw InputError(f.rgb_list_file, f.rgb_line,
                     "RGB image " + f.rgb_path + " is " + std::to_string(rgb.cols) + "x" +
                         std::to_string(rgb.rows) + ", camera (" + seq.camera_source + ") is " +
                         std::to_string(seq.camera.width) + "x" +
                         std::to_string(seq.camera.height));
}

}  // namespace

Sequence OpenSequence(const std::string& root_in, const SequenceOptions& options) {
  if (!(options.max_difference_s > 0))
    throw InputError("--max-diff", "max difference must be > 0 s, got " +
                                       FormatDouble17(options.max_difference_s));
  std::string root = root_in;
  while (root.size() > 1 && root.back() == '/') root.pop_back();
  if (!IsDir(root)) throw InputError(root, "sequence folder not found");
  Sequence seq;
  seq.root = root;
  seq.camera = ResolveSequenceCamera(root, options.camera, &seq.camera_source);
  if (!options.association_file.empty()) OpenSeqFromAssociationFile(root, options.association_file, &seq);
  else OpenSeqFromTumLists(root, options.max_difference_s, &seq);
  if (seq.frames.empty())
    throw InputError(seq.association_source, "zero associated RGB/depth pairs");
  for (const FrameEntry& f : seq.frames) {
    CheckImageListed(f.rgb_path, f.rgb_list_file, f.rgb_line, "RGB");
    CheckImageListed(f.depth_path, f.depth_list_file, f.depth_line, "depth");
  }
  OpenSeqCheckFirstPair(seq);
  const std::string gt = root + "/groundtruth.txt";
  if (IsFile(gt)) {
    const TumTrajectory traj = ReadTumTrajectory(gt);
    seq.groundtruth = traj.poses;
    seq.groundtruth_path = gt;
    seq.groundtruth_duplicates_dropped = traj.duplicates_dropped;
  }
  return seq;
}

cv::Mat LoadRgb(const Sequence& seq, const FrameEntry& frame) {
  const cv::Mat raw = dynref::ImageRead(frame.rgb_path, cv::IMREAD_UNCHANGED);
  if (raw.empty())
    throw InputError(frame.rgb_list_file, frame.rgb_line,
                     "cannot read RGB image " + frame.rgb_path);
  if (raw.depth() != CV_8U)
    throw InputError(frame.rgb_list_file, frame.rgb_line,
                     "RGB image " + frame.rgb_path + " is not 8-bit");
  // Gray or BGRA files are converted by the decoder to 3-channel BGR.
  const cv::Mat bgr = raw.channels() == 3 ? raw : dynref::ImageRead(frame.rgb_path, cv::IMREAD_COLOR);
  if (bgr.cols != seq.camera.width || bgr.rows != seq.camera.height)
    throw InputError(frame.rgb_list_file, frame.rgb_line,
                     "RGB image " + frame.rgb_path + " is " + std::to_string(bgr.cols) + "x" +
                         std::to_string(bgr.rows) + ", camera '" + seq.camera.name + "' is " +
                         std::to_string(seq.camera.width) + "x" +
                         std::to_string(seq.camera.height));
  return bgr;
}

cv::Mat LoadDepthMeters(const Sequence& seq, const FrameEntry& frame) {
  const cv::Mat raw = dynref::ImageRead(frame.depth_path, cv::IMREAD_UNCHANGED);
  if (raw.empty())
    throw InputError(frame.depth_list_file, frame.depth_line,
                     "cannot read depth image " + frame.depth_path);
  if (raw.depth() != CV_16U || raw.channels() != 1)
    throw InputError(frame.depth_list_file, frame.depth_line,
                     "depth image " + frame.depth_path + " is not a 1-channel 16-bit PNG (" +
                         std::to_string(8 * static_cast<int>(raw.elemSize1())) + "-bit, " +
                         std::to_string(raw.channels()) + " channel(s))");
  if (raw.cols != seq.camera.width || raw.rows != seq.camera.height)
    throw InputError(frame.depth_list_file, frame.depth_line,
                     "depth image " + frame.depth_path + " is " + std::to_string(raw.cols) +
                         "x" + std::to_string(raw.rows) + ", camera '" + seq.camera.name +
                         "' is " + std::to_string(seq.camera.width) + "x" +
                         std::to_string(seq.camera.height));
  cv::Mat metres;
  raw.convertTo(metres, CV_32F, 1.0 / seq.camera.depth_factor);
  return metres;
}

}  // namespace dynref
