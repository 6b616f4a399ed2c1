#include "dynamic/epi/nerf_export.h"

#include <cmath>
#include <stdexcept>

#include "geometry/triangulation.h"

namespace dynref::epi {

void TriangulationGates::Check() const {
  if (!(parallax_cos_max > 0 && parallax_cos_max < 1)) throw std::invalid_argument("parallax_cos_max must be in (0, 1)");
  if (!(reprojection_px > 0)) throw std::invalid_argument("reprojection_px must be > 0");
}

const char* TriangulatedName(Triangulated t) {
  switch (t) {
    case Triangulated::kOk: return "ok";
    case Triangulated::kParallax: return "parallax";
    case Triangulated::kBehind: return "behind";
    case Triangulated::kReprojection: return "reprojection";
    case Triangulated::kDegenerate: return "degenerate";
  }
  return "?";
}

namespace {

Eigen::Matrix<double, 3, 4> Projection(const Intrinsics& K, const SE3& T_cw) {
  Eigen::Matrix3d Km;
  Km << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
  Eigen::Matrix<double, 3, 4> Rt;
  Rt << T_cw.linear(), T_cw.translation();
  return Km * Rt;
}

}  // namespace

Triangulated TriangulateDlt(const Intrinsics& K, const SE3& T_cw0, const SE3& T_cw1, const Eigen::Vector2d& x0,
                            const Eigen::Vector2d& x1, const TriangulationGates& gates, Eigen::Vector3d* X,
                            TriangulationValues* values) {
  TriangulationValues v;
  if (values == nullptr) values = &v;
  // Parallax of the two viewing rays (world frame), tested before solving (ORB-SLAM2
  // LocalMapping::CreateNewMapPoints: cosParallaxRays < 0.9998).
  const Eigen::Vector3d r0 = T_cw0.linear().transpose() *
                             Eigen::Vector3d((x0.x() - K.cx) / K.fx, (x0.y() - K.cy) / K.fy, 1.0);
  const Eigen::Vector3d r1 = T_cw1.linear().transpose() *
                             Eigen::Vector3d((x1.x() - K.cx) / K.fx, (x1.y() - K.cy) / K.fy, 1.0);
  values->cos_parallax = r0.dot(r1) / (r0.norm() * r1.norm());
  if (values->cos_parallax >= gates.parallax_cos_max) return Triangulated::kParallax;
  Eigen::Vector3d Xw;
  if (!geometry::TriangulateLinear(Projection(K, T_cw0), Projection(K, T_cw1), x0, x1, &Xw))
    return Triangulated::kDegenerate;
  values->X = Xw;
  const Eigen::Vector3d c0 = T_cw0 * Xw, c1 = T_cw1 * Xw;
  values->z0 = c0.z(), values->z1 = c1.z();
  if (!(c0.z() > 0) || !(c1.z() > 0)) return Triangulated::kBehind;
  const double e0 = (K.Project(c0) - x0).norm(), e1 = (K.Project(c1) - x1).norm();
  values->err0 = e0, values->err1 = e1;
  if (!(e0 < gates.reprojection_px) || !(e1 < gates.reprojection_px)) return Triangulated::kReprojection;
  *X = Xw;
  return Triangulated::kOk;
}

Eigen::Matrix4d NerfTransformMatrix(const SE3& T_cw) {
  const SE3 T_wc = T_cw.inverse();
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = T_wc.linear();
  M.topRightCorner<3, 1>() = T_wc.translation();
  M.block<3, 1>(0, 1) *= -1.0;  // OpenCV y down -> OpenGL y up
  M.block<3, 1>(0, 2) *= -1.0;  // OpenCV z forward -> OpenGL z backwards
  return M;
}

nlohmann::json TransformsJson(const Camera& camera, const std::vector<NerfFrame>& frames,
                              const std::string& ply_file_path, const nlohmann::json& extra) {
  nlohmann::json j;
  j["camera_model"] = "OPENCV";
  j["fl_x"] = camera.fx;
  j["fl_y"] = camera.fy;
  j["cx"] = camera.cx;
  j["cy"] = camera.cy;
  j["w"] = camera.width;
  j["h"] = camera.height;
  j["k1"] = camera.k1;
  j["k2"] = camera.k2;
  j["p1"] = camera.p1;
  j["p2"] = camera.p2;
  j["k3"] = camera.k3;
  j["frames"] = nlohmann::json::array();
  for (const NerfFrame& f : frames) {
    nlohmann::json fj;
    fj["file_path"] = f.file_path;
    if (!f.mask_path.empty()) fj["mask_path"] = f.mask_path;
    const Eigen::Matrix4d M = NerfTransformMatrix(f.T_cw);
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({M(r, 0), M(r, 1), M(r, 2), M(r, 3)});
    fj["transform_matrix"] = rows;
    fj["dynref_keyframe_id"] = f.keyframe_id;
    j["frames"].push_back(fj);
  }
  if (!ply_file_path.empty()) j["ply_file_path"] = ply_file_path;
  j["dynref"] = extra;
  return j;
}

bool SampleRgb(const cv::Mat& bgr, double u, double v, Eigen::Vector3d* rgb) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("SampleRgb: need a CV_8UC3 BGR image");
  if (!(u >= 0 && v >= 0 && u <= bgr.cols - 1 && v <= bgr.rows - 1)) return false;
  const int x0 = std::min(static_cast<int>(u), bgr.cols - 2 < 0 ? 0 : bgr.cols - 2);
  const int y0 = std::min(static_cast<int>(v), bgr.rows - 2 < 0 ? 0 : bgr.rows - 2);
  const int x1 = std::min(x0 + 1, bgr.cols - 1), y1 = std::min(y0 + 1, bgr.rows - 1);
  const double a = u - x0, b = v - y0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  const auto add = [&](int x, int y, double w) {
    const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
    c += w * Eigen::Vector3d(p[2], p[1], p[0]);
  };
  add(x0, y0, (1 - a) * (1 - b));
  add(x1, y0, a * (1 - b));
  add(x0, y1, (1 - a) * b);
  add(x1, y1, a * b);
  *rgb = c / 255.0;
  return true;
}

}  // namespace dynref::epi
