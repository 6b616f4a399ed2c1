#include "io/mask_layers.h"

#include <sys/stat.h>

#include <fstream>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/image_file.h"

namespace dynref {

MaskLayersWriter::MaskLayersWriter(std::vector<MaskLayer> legend) : legend_(std::move(legend)) {}

void MaskLayersWriter::Add(const std::string& stamp_text, const cv::Mat& labels) {
  if (labels.type() != CV_8U) throw std::logic_error("MaskLayersWriter: labels must be CV_8U");
  if (cv::countNonZero(labels) == 0) return;
  std::vector<uchar> buf;
  if (!dynref::ImageEncode(".png", labels, buf)) throw std::runtime_error("cannot encode mask layer " + stamp_text);
  png_[stamp_text] = std::move(buf);
}

size_t MaskLayersWriter::Write(const std::string& dir) const {
  EnsureDirectory(dir);
  for (const auto& [stamp, buf] : png_) AtomicWriteFile(dir + "/" + stamp + ".png", std::string(buf.begin(), buf.end()));
  std::ostringstream legend;
  legend << "dynref-mask-layers 1\n";
  for (const MaskLayer& l : legend_) legend << l.value << ' ' << l.name << ' ' << l.r << ' ' << l.g << ' ' << l.b << '\n';
  AtomicWriteFile(dir + "/legend.txt", legend.str());
  return png_.size();
}

bool MaskLayersReader::Exists(const std::string& dir) {
  struct stat st {};
  return ::stat((dir + "/legend.txt").c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

MaskLayersReader::MaskLayersReader(const std::string& dir) : dir_(dir) {
  const std::string path = dir + "/legend.txt";
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open mask-layer legend");
  std::string line;
  if (!std::getline(in, line) || line != "dynref-mask-layers 1")
    throw InputError(path, 1, "expected 'dynref-mask-layers 1'");
  std::set<int> values;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::istringstream s(line);
    MaskLayer l;
    std::string extra;
    if (!(s >> l.value >> l.name >> l.r >> l.g >> l.b) || (s >> extra))
      throw InputError(path, n, "expected '<value> <name> <r> <g> <b>'");
    if (l.value < 1 || l.value > 255) throw InputError(path, n, "value must be in 1..255");
    for (int c : {l.r, l.g, l.b})
      if (c < 0 || c > 255) throw InputError(path, n, "colour components must be in 0..255");
    if (!values.insert(l.value).second) throw InputError(path, n, "value " + std::to_string(l.value) + " given twice");
    legend_.push_back(l);
  }
}

cv::Mat MaskLayersReader::Read(const std::string& stamp_text, cv::Size size) const {
  const std::string path = dir_ + "/" + stamp_text + ".png";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return {};
  const cv::Mat m = dynref::ImageRead(path, cv::IMREAD_UNCHANGED);
  if (m.empty() || m.type() != CV_8U) throw InputError(path, "not an 8-bit single-channel PNG");
  if (m.size() != size)
    throw InputError(path, "size " + std::to_string(m.cols) + "x" + std::to_string(m.rows) + " differs from the image");
  return m;
}

}  // namespace dynref
