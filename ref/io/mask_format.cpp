#include "io/mask_format.h"

#include "io/coco_classes.h"

#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "io/image_file.h"

namespace dynref {
namespace {

std::string StemFor(const std::string& stamp) { return stamp; }

std::vector<std::string> ReadLines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open file");
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (lines.empty()) RejectUtf8Bom(path, line);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  return lines;
}

bool IsSkippable(const std::string& line) {
  return line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#';
}

}  // namespace

cv::Mat FrameDetections::MaskOf(int instance_id) const {
  if (instance_ids.empty()) return {};
  cv::Mat mask = instance_ids == instance_id;
  return mask;
}

DetectionsWriter::DetectionsWriter(const std::string& dir, const std::string& source,
                                   const std::string& model_sha256)
    : dir_(dir) {
  EnsureDirectory(dir_);
  std::ostringstream f;
  f << "dynref-detections " << kMaskFormatVersion << "\nsource " << source << "\nmodel_sha256 "
    << (model_sha256.empty() ? "-" : model_sha256) << "\n";
  AtomicWriteFile(dir_ + "/format.txt", f.str());
}

void DetectionsWriter::Write(const FrameDetections& frame) {
  const std::string stem = StemFor(frame.stamp_text);
  std::ostringstream t;
  t << "# id class_id class_name confidence x_min y_min x_max y_max has_mask\n";
  bool any_mask = false;
  for (const auto& d : frame.instances) {
    t << d.id << ' ' << d.class_id << ' ' << (d.class_name.empty() ? "unknown" : d.class_name) << ' '
      << FormatDouble17(d.confidence) << ' ' << FormatDouble17(d.x_min) << ' '
      << FormatDouble17(d.y_min) << ' ' << FormatDouble17(d.x_max) << ' '
      << FormatDouble17(d.y_max) << ' ' << (d.has_mask ? 1 : 0) << '\n';
    any_mask = any_mask || d.has_mask;
  }
  if (any_mask) {
    if (frame.instance_ids.type() != CV_16U)
      throw std::runtime_error("DetectionsWriter: instance_ids must be CV_16U for " + stem);
    const std::string png = dir_ + "/" + stem + ".png";
    const std::string tmp = TempPathFor(png) + ".png";
    if (!dynref::ImageWrite(tmp, frame.instance_ids)) throw std::runtime_error("cannot write " + tmp);
    AtomicRename(tmp, png);
  }
  AtomicWriteFile(dir_ + "/" + stem + ".txt", t.str());
  index_.emplace_back(frame.stamp_text, stem);
}

void DetectionsWriter::Finish() {
  std::ostringstream o;
  o << "# rgb_stamp stem\n";
  for (const auto& [stamp, stem] : index_) o << stamp << ' ' << stem << '\n';
  AtomicWriteFile(dir_ + "/index.txt", o.str());
}

DetectionsReader::DetectionsReader(const std::string& dir) : dir_(dir) {
  const std::string fpath = dir_ + "/format.txt";
  const auto flines = ReadLines(fpath);
  int version = -1;
  for (size_t i = 0; i < flines.size(); ++i) {
    std::istringstream s(flines[i]);
    std::string key, value;
    s >> key >> value;
    if (key == "dynref-detections") {
      try {
        version = std::stoi(value);
      } catch (...) {
        throw InputError(fpath, int(i + 1), "bad version '" + value + "'");
      }
    } else if (key == "source") {
      source_ = value;
    } else if (key == "model_sha256") {
      model_sha256_ = value;
    }
  }
  if (version != kMaskFormatVersion)
    throw InputError(fpath, "not a dynref-detections " + std::to_string(kMaskFormatVersion) +
                                " folder (version " + std::to_string(version) + ")");
  const std::string ipath = dir_ + "/index.txt";
  const auto ilines = ReadLines(ipath);
  for (size_t i = 0; i < ilines.size(); ++i) {
    if (IsSkippable(ilines[i])) continue;
    std::istringstream s(ilines[i]);
    std::string stamp, stem, extra;
    if (!(s >> stamp >> stem) || (s >> extra))
      throw InputError(ipath, int(i + 1), "expected '<rgb_stamp> <stem>'");
    // A stamp must be a number (Stamps() sorts by it; a bad one used to end in a bare "stod"
    // in synth-montage, issue 20 item 10).
    char* end = nullptr;
    const double v = std::strtod(stamp.c_str(), &end);
    if (end == stamp.c_str() || *end != '\0' || !std::isfinite(v))
      throw InputError(ipath, int(i + 1), "stamp '" + stamp + "' is not a number");
    index_[stamp] = stem;
  }
}

std::vector<std::string> DetectionsReader::Stamps() const {
  std::vector<std::pair<double, std::string>> v;
  // strtod, not std::stod: the constructor accepted the stamp with strtod, and std::stod throws
  // out_of_range on a subnormal such as "1e-320" (found by tests/fuzz).
  for (const auto& kv : index_) v.emplace_back(std::strtod(kv.first.c_str(), nullptr), kv.first);
  std::sort(v.begin(), v.end());
  std::vector<std::string> out;
  for (auto& p : v) out.push_back(p.second);
  return out;
}

namespace {

// Every non-zero pixel of the instance-id PNG is an instance with a mask in the frame's .txt: a
// PNG of other ids gave the frame no masks without a word (issue 37).
void RequireListedIds(const FrameDetections& f, const std::string& png, const std::string& txt) {
  std::vector<bool> listed(65536, false), seen(65536, false);
  for (const DetectedInstance& d : f.instances) listed[static_cast<size_t>(d.id)] = d.has_mask;
  for (int y = 0; y < f.instance_ids.rows; ++y) {
    const uint16_t* row = f.instance_ids.ptr<uint16_t>(y);
    for (int x = 0; x < f.instance_ids.cols; ++x) seen[row[x]] = true;
  }
  for (size_t id = 1; id < seen.size(); ++id)
    if (seen[id] && !listed[id])
      throw InputError(png, "pixel value " + std::to_string(id) + " is not an instance with a mask in " + txt);
}

}  // namespace

FrameDetections DetectionsReader::Read(const std::string& stamp_text, cv::Size image_size) const {
  auto it = index_.find(stamp_text);
  if (it == index_.end()) throw InputError(dir_ + "/index.txt", "no detections for frame " + stamp_text);
  FrameDetections out;
  out.stamp_text = stamp_text;
  out.source = source_;
  const std::string tpath = dir_ + "/" + it->second + ".txt";
  const auto lines = ReadLines(tpath);
  bool any_mask = false;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (IsSkippable(lines[i])) continue;
    std::istringstream s(lines[i]);
    DetectedInstance d;
    int has_mask = 0;
    std::string extra;
    if (!(s >> d.id >> d.class_id >> d.class_name >> d.confidence >> d.x_min >> d.y_min >> d.x_max >>
          d.y_max >> has_mask) || (s >> extra))
      throw InputError(tpath, int(i + 1),
                       "expected 'id class_id class_name confidence x_min y_min x_max y_max has_mask'");
    if (d.id < 1 || d.id > 65535) throw InputError(tpath, int(i + 1), "instance id must be in 1..65535");
    if (d.class_id < -1 || d.class_id >= kCocoClassCount)  // issue 20 item 11: 999 was accepted
      throw InputError(tpath, int(i + 1), "class_id must be -1 (unknown) or a COCO id 0.." +
                                              std::to_string(kCocoClassCount - 1) + ", got " +
                                              std::to_string(d.class_id));
    if (!(d.confidence >= 0 && d.confidence <= 1))
      throw InputError(tpath, int(i + 1), "confidence must be in [0, 1]");
    if (!(d.x_max >= d.x_min && d.y_max >= d.y_min))
      throw InputError(tpath, int(i + 1), "box has max < min");
    d.has_mask = has_mask != 0;
    any_mask = any_mask || d.has_mask;
    out.instances.push_back(d);
  }
  std::sort(out.instances.begin(), out.instances.end(),
            [](const DetectedInstance& a, const DetectedInstance& b) { return a.id < b.id; });
  for (size_t i = 1; i < out.instances.size(); ++i)
    if (out.instances[i].id == out.instances[i - 1].id)
      throw InputError(tpath, "instance id " + std::to_string(out.instances[i].id) + " appears twice");
  if (any_mask) {
    const std::string png = dir_ + "/" + it->second + ".png";
    out.instance_ids = dynref::ImageRead(png, cv::IMREAD_UNCHANGED);
    if (out.instance_ids.empty()) throw InputError(png, "missing or corrupt instance-id PNG");
    if (out.instance_ids.type() != CV_16U)
      throw InputError(png, "instance-id PNG must be 16-bit single channel");
    if (!image_size.empty() && out.instance_ids.size() != image_size)
      throw InputError(png, "instance-id PNG is " + std::to_string(out.instance_ids.cols) + "x" +
                                std::to_string(out.instance_ids.rows) + ", the images are " +
                                std::to_string(image_size.width) + "x" +
                                std::to_string(image_size.height));
    RequireListedIds(out, png, tpath);
  }
  return out;
}

}  // namespace dynref
