#include "io/camera.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
    throw InputError(path, "camera YAML not found");
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML))
      throw InputError(path, "cannot open camera YAML (missing or unreadable)");
  } catch (const cv::Exception& e) {
    throw InputError(path, std::string("not a readable ORB-SLAM2 camera YAML: ") + e.what());
  }
  auto number = [&](const std::string& key, bool mandatory, double fallback) {
    const cv::FileNode node = fs[key];
    if (node.empty() || node.isNone()) {
      if (mandatory) throw InputError(path, "missing mandatory key '" + key + "'");
      return fallback;
    }
    if (!node.isReal() && !node.isInt())
      throw InputError(path, "key '" + key + "' is not a number");
    const double v = static_cast<double>(node);
    if (!std::isfinite(v)) throw InputError(path, "key '" + key + "' is not finite");
    return v;
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
  c.width = static_cast<int>(number("Camera.width", false, 640));
  c.height = static_cast<int>(number("Camera.height", false, 480));
  c.bf = number("Camera.bf", false, 40.0);
  c.th_depth = number("ThDepth", false, 40.0);
  c.depth_factor = number("DepthMapFactor", true, 5000.0);
  if (c.fx <= 0 || c.fy <= 0) throw InputError(path, "Camera.fx and Camera.fy must be positive");
  if (c.width <= 0 || c.height <= 0)
    throw InputError(path, "Camera.width and Camera.height must be positive");
  if (c.depth_factor <= 0) throw InputError(path, "DepthMapFactor must be positive");
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
