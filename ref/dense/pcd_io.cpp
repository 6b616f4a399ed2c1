#include "dense/pcd_io.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace dynref::dense {

void WritePcd(const std::string& path, const PointCloud& cloud) {
  AtomicOutputFile out(path, true);
  std::ostream& os = out.stream();
  os << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\n"
     << "TYPE F F F F\nCOUNT 1 1 1 1\nWIDTH " << cloud.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
     << "POINTS " << cloud.size() << "\nDATA binary\n";
  for (const ColoredPoint& p : cloud) {
    const uint32_t rgb = (uint32_t(p.r) << 16) | (uint32_t(p.g) << 8) | uint32_t(p.b);
    float packed;
    std::memcpy(&packed, &rgb, 4);
    const float v[4] = {p.x, p.y, p.z, packed};
    os.write(reinterpret_cast<const char*>(v), sizeof(v));  // little-endian host (x86-64)
  }
  out.Commit();
}

PointCloud ReadPcd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open PCD file");
  std::string line;
  size_t points = 0;
  int n = 0, points_line = 0;
  bool fields_ok = false, data = false;
  while (std::getline(in, line)) {
    ++n;
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "FIELDS") fields_ok = line == "FIELDS x y z rgb";
    if (key == "POINTS") {
      // Digits only: "-5" must not wrap around to a huge size_t (issue 37).
      std::string text;
      ss >> text;
      if (text.empty() || text.size() > 15 || text.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(path, n, "POINTS '" + text + "' is not a whole number >= 0");
      points = static_cast<size_t>(std::stoull(text));
      points_line = n;
    }
    if (key == "DATA") {
      if (line != "DATA binary") throw InputError(path, n, "only DATA binary is read");
      data = true;
      break;
    }
  }
  if (!fields_ok) throw InputError(path, "expected FIELDS x y z rgb");
  if (!data) throw InputError(path, n, "no DATA line");
  if (!points_line) throw InputError(path, n, "no POINTS line before DATA");
  // The data must be exactly what POINTS declares: fewer bytes is a truncated file, more is data
  // the header does not declare.
  const std::streampos here = in.tellg();
  in.seekg(0, std::ios::end);
  const uint64_t left = here < 0 ? 0 : static_cast<uint64_t>(in.tellg() - here);
  in.seekg(here);
  const uint64_t expected = uint64_t(points) * 16;
  const std::string declared = std::to_string(points) + " points (line " + std::to_string(points_line) + ")";
  if (left < expected)
    throw InputError(path, "truncated: the header declares " + declared + " = " + std::to_string(expected) +
                               " bytes of data, only " + std::to_string(left) + " follow");
  if (left > expected)
    throw InputError(path, std::to_string(left - expected) + " bytes of data after the " + declared +
                               " the header declares");
  PointCloud cloud(points);
  for (size_t i = 0; i < points; ++i) {
    float v[4];
    if (!in.read(reinterpret_cast<char*>(v), sizeof(v))) throw InputError(path, "truncated binary data");
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
      throw InputError(path, "point " + std::to_string(i) + " has a non-finite coordinate");
    uint32_t rgb;
    std::memcpy(&rgb, &v[3], 4);
    cloud[i].x = v[0], cloud[i].y = v[1], cloud[i].z = v[2];
    cloud[i].r = uint8_t(rgb >> 16), cloud[i].g = uint8_t(rgb >> 8), cloud[i].b = uint8_t(rgb);
  }
  return cloud;
}

}  // namespace dynref::dense
