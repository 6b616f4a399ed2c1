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

namespace {

void PutU32LE(std::ostream& out, uint32_t v) {
  const char b[4] = {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
                     static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
  out.write(b, 4);
}

uint32_t GetU32LE(const unsigned char* b) {
  return static_cast<uint32_t>(b[0]) | (static_cast<uint32_t>(b[1]) << 8) | (static_cast<uint32_t>(b[2]) << 16) |
         (static_cast<uint32_t>(b[3]) << 24);
}

}  // namespace

void WritePlyMesh(const std::string& path, const TriangleMesh& mesh, const std::string& comment) {
  AtomicOutputFile file(path, /*binary=*/true);
  std::ostream& out = file.stream();
  out << "ply\nformat binary_little_endian 1.0\n";
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) out << "comment " << line << "\n";
  out << "element vertex " << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.faces.size() << "\nproperty list uchar uint vertex_indices\nend_header\n";
  for (const auto& v : mesh.vertices)
    for (float c : v) PutFloatLE(out, c);
  for (const auto& f : mesh.faces) {
    out.put(static_cast<char>(3));
    for (uint32_t i : f) PutU32LE(out, i);
  }
  file.Commit();
}

TriangleMesh ReadPlyMesh(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open PLY file");
  std::vector<std::string> header;
  size_t vertices = 0, faces = 0;
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (line == "end_header") break;
    if (line_no == 1 && line != "ply") throw InputError(path, 1, "not a PLY file");
    if (line.rfind("comment", 0) == 0) continue;
    std::istringstream ss(line);
    std::string word, name;
    ss >> word;
    if (word == "element") {
      size_t n = 0;
      ss >> name >> n;
      (name == "vertex" ? vertices : faces) = n;
    }
    header.push_back(word == "element" ? word + " " + name : line);
  }
  const std::vector<std::string> expected = {"ply", "format binary_little_endian 1.0", "element vertex", "property float x",
                                             "property float y", "property float z", "element face",
                                             "property list uchar uint vertex_indices"};
  if (header != expected) throw InputError(path, "not a dynref triangle-mesh PLY (binary, float xyz, uchar/uint faces)");
  TriangleMesh m;
  m.vertices.resize(vertices);
  for (auto& v : m.vertices) {
    unsigned char b[12];
    if (!in.read(reinterpret_cast<char*>(b), 12)) throw InputError(path, "truncated PLY vertex list");
    v = {GetFloatLE(b), GetFloatLE(b + 4), GetFloatLE(b + 8)};
  }
  m.faces.resize(faces);
  for (size_t i = 0; i < faces; ++i) {
    unsigned char b[13];
    if (!in.read(reinterpret_cast<char*>(b), 13)) throw InputError(path, "truncated PLY face list");
    if (b[0] != 3) throw InputError(path, "face " + std::to_string(i) + " is not a triangle");
    for (int k = 0; k < 3; ++k) {
      m.faces[i][static_cast<size_t>(k)] = GetU32LE(b + 1 + 4 * k);
      if (m.faces[i][static_cast<size_t>(k)] >= vertices)
        throw InputError(path, "face " + std::to_string(i) + " names vertex " + std::to_string(m.faces[i][static_cast<size_t>(k)]) +
                                   " of " + std::to_string(vertices));
    }
  }
  return m;
}

}  // namespace dynref::dense
