#include "dense/ply_writer.h"

#include <cstring>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"

namespace dynref::dense {
namespace {

void PutFloatLE(std::ostream& out, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  const char b[4] = {static_cast<char>(bits & 0xff), static_cast<char>((bits >> 8) & 0xff),
                     static_cast<char>((bits >> 16) & 0xff), static_cast<char>((bits >> 24) & 0xff)};
  out.write(b, 4);
}

float GetFloatLE(const unsigned char* b) {
  const uint32_t bits = static_cast<uint32_t>(b[0]) | (static_cast<uint32_t>(b[1]) << 8) |
                        (static_cast<uint32_t>(b[2]) << 16) | (static_cast<uint32_t>(b[3]) << 24);
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

}  // namespace

void WritePly(const std::string& path, const PointCloud& cloud, PlyFormat format,
              const std::string& comment) {
  // Bytes are assembled explicitly (PutFloatLE): no dependency on the host byte order.
  AtomicOutputFile file(path, /*binary=*/true);
  std::ostream& out = file.stream();
  out << "ply\nformat " << (format == PlyFormat::kAscii ? "ascii" : "binary_little_endian")
      << " 1.0\n";
  if (!comment.empty()) {
    std::istringstream lines(comment);
    std::string line;
    while (std::getline(lines, line)) out << "comment " << line << "\n";
  }
  out << "element vertex " << cloud.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (const ColoredPoint& p : cloud) {
    if (format == PlyFormat::kAscii) {
      out << FormatDouble17(p.x) << ' ' << FormatDouble17(p.y) << ' ' << FormatDouble17(p.z) << ' '
          << int(p.r) << ' ' << int(p.g) << ' ' << int(p.b) << '\n';
    } else {
      PutFloatLE(out, p.x);
      PutFloatLE(out, p.y);
      PutFloatLE(out, p.z);
      const char c[3] = {static_cast<char>(p.r), static_cast<char>(p.g), static_cast<char>(p.b)};
      out.write(c, 3);
    }
  }
  file.Commit();
}

PointCloud ReadPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open PLY file");
  std::string line;
  int line_no = 0;
  bool ascii = false, binary = false;
  size_t count = 0;
  std::vector<std::string> props;
  while (std::getline(in, line)) {
    ++line_no;
    if (line == "end_header") break;
    std::istringstream ss(line);
    std::string word;
    ss >> word;
    if (line_no == 1 && word != "ply") throw InputError(path, 1, "not a PLY file");
    if (word == "format") {
      std::string f;
      ss >> f;
      ascii = f == "ascii";
      binary = f == "binary_little_endian";
      if (!ascii && !binary) throw InputError(path, line_no, "unsupported PLY format '" + f + "'");
    } else if (word == "element") {
      std::string name;
      ss >> name >> count;
      if (name != "vertex") throw InputError(path, line_no, "only a vertex element is supported");
    } else if (word == "property") {
      std::string type, name;
      ss >> type >> name;
      props.push_back(type + " " + name);
    }
  }
  const std::vector<std::string> expected = {"float x", "float y", "float z",
                                             "uchar red", "uchar green", "uchar blue"};
  if (props != expected) throw InputError(path, "unexpected PLY vertex properties");
  PointCloud cloud(count);
  for (size_t i = 0; i < count; ++i) {
    ColoredPoint& p = cloud[i];
    if (ascii) {
      int r, g, b;
      if (!(in >> p.x >> p.y >> p.z >> r >> g >> b)) throw InputError(path, "truncated ASCII PLY");
      p.r = static_cast<uint8_t>(r), p.g = static_cast<uint8_t>(g), p.b = static_cast<uint8_t>(b);
    } else {
      unsigned char buf[15];
      if (!in.read(reinterpret_cast<char*>(buf), 15)) throw InputError(path, "truncated binary PLY");
      p.x = GetFloatLE(buf), p.y = GetFloatLE(buf + 4), p.z = GetFloatLE(buf + 8);
      p.r = buf[12], p.g = buf[13], p.b = buf[14];
    }
  }
  return cloud;
}

}  // namespace dynref::dense
