// Pinhole RGB-D camera with Brown-Conrady distortion (OpenCV order k1 k2 p1 p2 k3),
// as in TUM's published calibration and ORB-SLAM2's camera YAML.
#pragma once
#include <opencv2/core.hpp>
#include <string>

#include "core/intrinsics.h"

namespace dynref {

struct Camera {
  std::string name;              // preset name or YAML path it came from
  int width = 640, height = 480;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  double depth_factor = 5000.0;  // depth PNG units per metre (TUM: 5000)
  double bf = 40.0;              // ORB-SLAM2 Camera.bf: virtual stereo baseline * fx (px*m)
  double th_depth = 40.0;        // ORB-SLAM2 ThDepth: close/far threshold in baselines

  bool HasDistortion() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0 || k3 != 0; }
  cv::Matx33d K() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
  cv::Mat DistCoeffs() const { return (cv::Mat_<double>(1, 5) << k1, k2, p1, p2, k3); }
  double baseline_m() const { return bf / fx; }
  // Raw (distorted) pixel of an undistorted pixel: the forward Brown-Conrady model (OpenCV's
  // k1 k2 p1 p2 k3); identity without distortion.
  cv::Point2d Distort(double u, double v) const {
    if (!HasDistortion()) return {u, v};
    const double x = (u - cx) / fx, y = (v - cy) / fy, r2 = x * x + y * y;
    const double radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
    const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    return {fx * xd + cx, fy * yd + cy};
  }
  // The pinhole part (core/intrinsics.h): fx, fy, cx, cy, bf, width, height.
  Intrinsics Pinhole() const { return {fx, fy, cx, cy, bf, width, height}; }
};

// Presets: "tum_fr1", "tum_fr2", "tum_fr3", "bonn", "synthetic" (= TUM fr3 intrinsics, no distortion).
// Throws InputError for an unknown name, listing the known ones.
Camera CameraPreset(const std::string& name);
// True for the preset names CameraPreset accepts.
bool IsCameraPresetName(const std::string& name);
// ORB-SLAM2 style YAML (%YAML:1.0, Camera.fx ... Camera.k3, Camera.width/height, Camera.bf,
// ThDepth, DepthMapFactor). Missing mandatory keys are errors naming the file and key; duplicate
// keys and out-of-range values (fx, fy, bf, fps, DepthMapFactor <= 0, principal point outside the
// image, Camera.RGB not 0/1) are errors naming the file and line.
Camera ReadOrbSlamCameraYaml(const std::string& path);
// Writes the same YAML format (used by `dynref synth`), atomically.
void WriteOrbSlamCameraYaml(const Camera& camera, const std::string& path);

}  // namespace dynref
