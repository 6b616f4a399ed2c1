#include "dense/pcd_io.h"

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
  int n = 0;
  bool fields_ok = false;
  while (std::getline(in, line)) {
    ++n;
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "FIELDS") fields_ok = line == "FIELDS x y z rgb";
    if (key == "POINTS") ss >> points;
    if (key == "DATA") {
      if (line != "DATA binary") throw InputError(path, n, "only DATA binary is read");
      break;
    }
  }
  if (!fields_ok) throw InputError(path, "expected FIELDS x y z rgb");
  PointCloud cloud(points);
  for (size_t i = 0; i < points; ++i) {
    float v[4];
    if (!in.read(reinterpret_cast<char*>(v), sizeof(v))) throw InputError(path, "truncated binary data");
    uint32_t rgb;
    std::memcpy(&rgb, &v[3], 4);
    cloud[i].x = v[0], cloud[i].y = v[1], cloud[i].z = v[2];
    cloud[i].r = uint8_t(rgb >> 16), cloud[i].g = uint8_t(rgb >> 8), cloud[i].b = uint8_t(rgb);
  }
  return cloud;
}

}  // namespace dynref::dense
