#include "io/camera.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <opencv2/core/persistence.hpp>
#include <sstream>
#include <sys/stat.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace dynref {
namespace {

Camera Make(const std::string& name, double fx, double fy, double cx, double cy,
            std::array<double, 5> d) {
  Camera c;
  c.name = name;
  c.width = 640;
  c.height = 480;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  c.k1 = d[0];
  c.k2 = d[1];
  c.p1 = d[2];
  c.p2 = d[3];
  c.k3 = d[4];
  c.depth_factor = 5000.0;  // TUM and Bonn: 16-bit PNG, 5000 units per metre
  c.bf = 40.0;              // ORB-SLAM2 TUM1/2/3.yaml
  c.th_depth = 40.0;
  return c;
}

// Shortest decimal text that reads back to exactly v (YAML values must round-trip).
std::string Shortest(double v) {
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  std::string s = buf;
  // Keep a decimal point so YAML/FileStorage types the value as a real.
  if (s.find_first_of(".eE") == std::string::npos && s.find_first_of("ni") == std::string::npos)
    s += ".0";
  return s;
}

// 1-based line of every top-level key of an ORB-SLAM2 settings file. cv::FileStorage reports no
// lines and silently keeps the first of two equal keys, so the text is scanned for both: a key
// given twice is an InputError naming the second line. Indented lines (the rows/cols/data of an
// !!opencv-matrix), comments and directives are skipped.
std::map<std::string, int> TopLevelKeyLines(const std::string& path) {
  std::map<std::string, int> lines;
  std::ifstream in(path);
  std::string text;
  for (int n = 1; std::getline(in, text); ++n) {
    if (n == 1) RejectUtf8Bom(path, text);
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.empty() || std::string(" \t#%-.{[").find(text[0]) != std::string::npos) continue;
    const size_t colon = text.find(':');
    if (colon == std::string::npos) continue;
    std::string key = text.substr(0, colon);
    while (!key.empty() && (key.back() == ' ' || key.back() == '\t')) key.pop_back();
    if (key.size() >= 2 && (key[0] == '"' || key[0] == '\'') && key.back() == key[0])
      key = key.substr(1, key.size() - 2);
    const auto [it, inserted] = lines.emplace(key, n);
    if (!inserted)
      throw InputError(path, n, "duplicate key '" + key + "' (first given at line " +
                                    std::to_string(it->second) + ")");
  }
  return lines;
}

}  // namespace

Camera CameraPreset(const std::string& name) {
  // TUM RGB-D published calibration (vision.in.tum.de/data/datasets/rgbd-dataset/file_formats,
  // "Intrinsic Camera Calibration of the Kinect"), ROS default order d0..d4 = k1 k2 p1 p2 k3.
  if (name == "tum_fr1")
    return Make(name, 517.3, 516.5, 318.6, 255.3, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633});
  if (name == "tum_fr2")
    return Make(name, 520.9, 521.0, 325.1, 249.7, {0.2312, -0.7849, -0.0033, -0.0001, 0.9172});
  if (name == "tum_fr3") return Make(name, 535.4, 539.2, 320.1, 247.6, {0, 0, 0, 0, 0});
  // Bonn RGB-D Dynamic dataset calibration (Palazzolo et al., IROS 2019, dataset web page).
  if (name == "bonn")
    return Make(name, 542.822841, 542.576870, 315.593520, 237.756098,
                {0.039903, -0.099343, -0.000730, -0.000144, 0.0});
  // dynref synthetic sequences: TUM fr3 intrinsics, ideal pinhole.
  if (name == "synthetic") return Make(name, 535.4, 539.2, 320.1, 247.6, {0, 0, 0, 0, 0});
  throw InputError("--camera", "unknown camera preset '" + name +
                                   "' (known: tum_fr1, tum_fr2, tum_fr3, bonn, synthetic, or a "
                                   "path to an ORB-SLAM2 camera YAML)");
}

bool IsCameraPresetName(const std::string& name) {
  return name == "tum_fr1" || name == "tum_fr2" || name == "tum_fr3" || name == "bonn" ||
         name == "synthetic";
}

Camera ReadOrbSlamCameraYaml(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, "camera YAML not found");
  if (!S_ISREG(st.st_mode)) throw InputError(path, "camera YAML is not a regular file");
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML))
      throw InputError(path, "cannot open camera YAML (missing or unreadable)");
    // A top level that is a list or a scalar would make every fs[key] an OpenCV assertion.
    if (!fs.root().isMap()) throw InputError(path, "top level must be a map of Camera.* keys");
  } catch (const cv::Exception& e) {
    throw InputError(path, std::string("not a readable ORB-SLAM2 camera YAML: ") + e.what());
  }
  const std::map<std::string, int> key_lines = TopLevelKeyLines(path);
  auto line_of = [&](const std::string& key) {
    const auto it = key_lines.find(key);
    return it == key_lines.end() ? 0 : it->second;
  };
  auto bad = [&](const std::string& key, const std::string& what) {
    throw InputError(path, line_of(key), key + " " + what);
  };
  auto number = [&](const std::string& key, bool mandatory, double fallback) {
    cv::FileNode node;
    try {
      node = fs[key];
    } catch (const cv::Exception& e) {
      throw InputError(path, line_of(key), "cannot read key '" + key + "': " + e.what());
    }
    if (node.empty() || node.isNone()) {
      if (mandatory) throw InputError(path, "missing mandatory key '" + key + "'");
      return fallback;
    }
    if (!node.isReal() && !node.isInt())
      throw InputError(path, line_of(key), "key '" + key + "' is not a number");
    const double v = static_cast<double>(node);
    if (!std::isfinite(v)) throw InputError(path, line_of(key), "key '" + key + "' is not finite");
    return v;
  };
  // Image size: checked as a number before the int conversion (a huge value would not fit).
  auto size = [&](const std::string& key, double fallback) {
    const double v = number(key, false, fallback);
    if (!(v >= 1 && v <= 100000) || v != std::floor(v)) bad(key, "must be an integer in 1..100000");
    return static_cast<int>(v);
  };
  Camera c;
  c.name = path;
  c.fx = number("Camera.fx", true, 0);
  c.fy = number("Camera.fy", true, 0);
  c.cx = number("Camera.cx", true, 0);
  c.cy = number("Camera.cy", true, 0);
  c.k1 = number("Camera.k1", true, 0);
  c.k2 = number("Camera.k2", true, 0);
  c.p1 = number("Camera.p1", true, 0);
  c.p2 = number("Camera.p2", true, 0);
  c.k3 = number("Camera.k3", false, 0);  // ORB-SLAM2 reads k3 only when present
  c.width = size("Camera.width", 640);
  c.height = size("Camera.height", 480);
  c.bf = number("Camera.bf", false, 40.0);
  c.th_depth = number("ThDepth", false, 40.0);
  c.depth_factor = number("DepthMapFactor", true, 5000.0);
  // Read only to be validated (dynref takes fps and the channel order from elsewhere).
  const double fps = number("Camera.fps", false, 30.0);
  const double rgb = number("Camera.RGB", false, 1.0);
  // Ranges (issue 37): positive, and below 1e6 (focal lengths in px, bf in px * m, DepthMapFactor
  // in units per m, fps): a larger value is a unit mistake, not a camera.
  auto positive = [&](const std::string& key, double v, double hi, const std::string& what) {
    if (!(v > 0 && v <= hi)) bad(key, "must be positive" + what + " and at most " + Shortest(hi) + ", got " + Shortest(v));
  };
  positive("Camera.fx", c.fx, 1e6, "");
  positive("Camera.fy", c.fy, 1e6, "");
  // ThDepth: close / far split at ThDepth baselines (ORB-SLAM2 Tracking: mThDepth = bf * ThDepth / fx).
  positive("ThDepth", c.th_depth, 1e4, " (close points are nearer than ThDepth baselines)");
  // The principal point lies inside the image (ORB-SLAM2's undistortion and grid assume it).
  if (!(c.cx >= 0 && c.cx < c.width))
    bad("Camera.cx", "must lie inside the image (0 <= cx < width " + std::to_string(c.width) + ")");
  if (!(c.cy >= 0 && c.cy < c.height))
    bad("Camera.cy",
        "must lie inside the image (0 <= cy < height " + std::to_string(c.height) + ")");
  positive("Camera.bf", c.bf, 1e6, " (baseline * fx)");
  positive("Camera.fps", fps, 1e4, "");
  if (rgb != 0 && rgb != 1) bad("Camera.RGB", "must be 0 (BGR) or 1 (RGB)");
  positive("DepthMapFactor", c.depth_factor, 1e6, "");
  return c;
}

void WriteOrbSlamCameraYaml(const Camera& camera, const std::string& path) {
  // Written as text: cv::FileStorage refuses '.' in key names when writing, but reads them
  // (ORB-SLAM2 files are read with cv::FileStorage, so this is exactly what it expects).
  std::ostringstream s;
  s << "%YAML:1.0\n"
    << "# dynref camera '" << camera.name << "' (ORB-SLAM2 RGB-D settings format)\n"
    << "Camera.fx: " << Shortest(camera.fx) << "\n"
    << "Camera.fy: " << Shortest(camera.fy) << "\n"
    << "Camera.cx: " << Shortest(camera.cx) << "\n"
    << "Camera.cy: " << Shortest(camera.cy) << "\n"
    << "Camera.k1: " << Shortest(camera.k1) << "\n"
    << "Camera.k2: " << Shortest(camera.k2) << "\n"
    << "Camera.p1: " << Shortest(camera.p1) << "\n"
    << "Camera.p2: " << Shortest(camera.p2) << "\n"
    << "Camera.k3: " << Shortest(camera.k3) << "\n"
    << "Camera.width: " << camera.width << "\n"
    << "Camera.height: " << camera.height << "\n"
    << "Camera.fps: 30.0\n"
    << "Camera.bf: " << Shortest(camera.bf) << "\n"
    << "Camera.RGB: 1\n"
    << "ThDepth: " << Shortest(camera.th_depth) << "\n"
    << "DepthMapFactor: " << Shortest(camera.depth_factor) << "\n";
  AtomicWriteFile(path, s.str());
}

}  // namespace dynref
