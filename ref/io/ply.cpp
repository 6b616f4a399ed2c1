#include "io/ply.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"

namespace dynref {
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

namespace {

// A header count ("element vertex 100"): decimal digits only (no sign, no exponent), so
// "-5" or "1e3" is an error naming the line instead of a wrapped-around size_t (issue 37).
size_t ParseCount(const std::string& path, int line_no, const std::string& what, const std::string& text) {
  if (text.empty() || text.size() > 15 || text.find_first_not_of("0123456789") != std::string::npos)
    throw InputError(path, line_no, what + " count '" + text + "' is not a whole number >= 0");
  return static_cast<size_t>(std::stoull(text));
}

// Bytes from the current position to the end of the file (the position is kept).
uint64_t BytesLeft(std::ifstream& in) {
  const std::streampos here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streampos end = in.tellg();
  in.seekg(here);
  return here < 0 || end < here ? 0 : static_cast<uint64_t>(end - here);
}

// The declared data size must be exactly what follows the header: fewer bytes is a truncated
// file, more is data the header does not declare (issue 37: map-eval read 100 of 642,749
// vertices because the header said 100).
void CheckDataSize(const std::string& path, uint64_t expected, uint64_t present, const std::string& declared) {
  if (present < expected)
    throw InputError(path, "truncated: the header declares " + declared + " = " + std::to_string(expected) +
                               " bytes of data, only " + std::to_string(present) + " follow");
  if (present > expected)
    throw InputError(path, std::to_string(present - expected) + " bytes of data after the " + declared +
                               " the header declares (count wrong, or the file was appended to)");
}

// Non-finite coordinates (NaN, inf) would turn every statistic computed from the cloud into nan.
void RequireFinite(const std::string& path, int line_no, size_t index, float x, float y, float z) {
  if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) return;
  throw InputError(path, line_no, "vertex " + std::to_string(index) + " has a non-finite coordinate (" +
                                      FormatDouble17(x) + " " + FormatDouble17(y) + " " + FormatDouble17(z) + ")");
}

}  // namespace

PointCloud ReadPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open PLY file");
  std::string line;
  int line_no = 0;
  bool ascii = false, binary = false, end_header = false;
  size_t count = 0;
  int count_line = 0;
  std::vector<std::string> props;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line == "end_header") {
      end_header = true;
      break;
    }
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
      std::string name, n;
      ss >> name >> n;
      if (name != "vertex") throw InputError(path, line_no, "only a vertex element is supported");
      if (count_line) throw InputError(path, line_no, "second vertex element (first on line " + std::to_string(count_line) + ")");
      count = ParseCount(path, line_no, "vertex", n);
      count_line = line_no;
    } else if (word == "property") {
      std::string type, name;
      ss >> type >> name;
      props.push_back(type + " " + name);
    }
  }
  if (line_no == 0) throw InputError(path, "empty file: not a PLY file");
  if (!end_header) throw InputError(path, line_no, "no end_header line");
  if (!ascii && !binary) throw InputError(path, line_no, "no format line before end_header");
  if (!count_line) throw InputError(path, line_no, "no 'element vertex N' line before end_header");
  const std::vector<std::string> expected = {"float x", "float y", "float z",
                                             "uchar red", "uchar green", "uchar blue"};
  if (props != expected) throw InputError(path, line_no, "unexpected PLY vertex properties");
  const std::string declared = std::to_string(count) + " vertices (line " + std::to_string(count_line) + ")";
  PointCloud cloud;
  if (binary) {
    CheckDataSize(path, uint64_t(count) * 15, BytesLeft(in), declared);
    cloud.resize(count);
    for (size_t i = 0; i < count; ++i) {
      ColoredPoint& p = cloud[i];
      unsigned char buf[15];
      if (!in.read(reinterpret_cast<char*>(buf), 15)) throw InputError(path, "truncated binary PLY");
      p.x = GetFloatLE(buf), p.y = GetFloatLE(buf + 4), p.z = GetFloatLE(buf + 8);
      p.r = buf[12], p.g = buf[13], p.b = buf[14];
      RequireFinite(path, 0, i, p.x, p.y, p.z);
    }
    return cloud;
  }
  // ASCII: one vertex per line ("x y z r g b"); blank lines are ignored.
  const uint64_t left = BytesLeft(in);
  if (uint64_t(count) > left / 12)  // "0 0 0 0 0 0\n" is the shortest vertex line
    throw InputError(path, "truncated: the header declares " + declared + ", only " + std::to_string(left) +
                               " bytes follow");
  cloud.reserve(count);
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (cloud.size() == count)
      throw InputError(path, line_no, "data after the " + declared + " the header declares");
    std::istringstream ss(line);
    std::string tok[6], extra;
    for (std::string& t : tok) ss >> t;
    if (tok[5].empty() || (ss >> extra)) throw InputError(path, line_no, "expected 'x y z red green blue'");
    ColoredPoint p;
    float* xyz[3] = {&p.x, &p.y, &p.z};
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      *xyz[k] = std::strtof(tok[k].c_str(), &end);
      if (*end) throw InputError(path, line_no, "'" + tok[k] + "' is not a number");
    }
    RequireFinite(path, line_no, cloud.size(), p.x, p.y, p.z);
    uint8_t* rgb[3] = {&p.r, &p.g, &p.b};
    for (int k = 0; k < 3; ++k) {
      const std::string& t = tok[3 + k];
      if (t.size() > 3 || t.find_first_not_of("0123456789") != std::string::npos || std::stoi(t) > 255)
        throw InputError(path, line_no, "colour '" + t + "' is not an integer in 0..255");
      *rgb[k] = static_cast<uint8_t>(std::stoi(t));
    }
    cloud.push_back(p);
  }
  if (cloud.size() != count)
    throw InputError(path, line_no, "truncated ASCII PLY: " + std::to_string(cloud.size()) + " of the " + declared);
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
      std::string n;
      ss >> name >> n;
      (name == "vertex" ? vertices : faces) = ParseCount(path, line_no, name, n);
    }
    header.push_back(word == "element" ? word + " " + name : line);
  }
  const std::vector<std::string> expected = {"ply", "format binary_little_endian 1.0", "element vertex", "property float x",
                                             "property float y", "property float z", "element face",
                                             "property list uchar uint vertex_indices"};
  if (header != expected) throw InputError(path, "not a dynref triangle-mesh PLY (binary, float xyz, uchar/uint faces)");
  CheckDataSize(path, uint64_t(vertices) * 12 + uint64_t(faces) * 13, BytesLeft(in),
                std::to_string(vertices) + " vertices and " + std::to_string(faces) + " faces");
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

}  // namespace dynref
