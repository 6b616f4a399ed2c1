#include "optim/synthetic_problem.h"

#include <cmath>

#include "core/rng.h"

namespace dynref::optim {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr double kScaleFactor = 1.2;  // ORB-SLAM2 ORBextractor.scaleFactor

SE3 Perturb(const SE3& T, double sigma_m, double sigma_rad, Rng& rng) {
  Eigen::Vector3d omega(rng.Gaussian(), rng.Gaussian(), rng.Gaussian());
  Eigen::Vector3d dt(rng.Gaussian(), rng.Gaussian(), rng.Gaussian());
  omega *= sigma_rad;
  dt *= sigma_m;
  SE3 D = SE3::Identity();
  const double angle = omega.norm();
  if (angle > 0) D.linear() = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
  D.translation() = dt;
  return D * T;
}

bool Project(const Intrinsics& K, const Eigen::Vector3d& X_c, Eigen::Vector2d* uv) {
  if (X_c.z() <= 0.1) return false;
  *uv = Eigen::Vector2d(K.fx * X_c.x() / X_c.z() + K.cx, K.fy * X_c.y() / X_c.z() + K.cy);
  return uv->x() >= 0 && uv->x() < kWidth && uv->y() >= 0 && uv->y() < kHeight;
}

// Noisy (or, for outliers, random) measurement of X_c at the given octave.
void Measure(const Intrinsics& K, const Eigen::Vector3d& X_c, int octave, double noise_px,
             bool outlier, bool stereo, Rng& rng, Eigen::Vector2d* uv, double* u_right,
             double* inv_sigma2) {
  const double scale = std::pow(kScaleFactor, octave);
  *inv_sigma2 = 1.0 / (scale * scale);
  const double sigma = noise_px * scale;
  const double u = K.fx * X_c.x() / X_c.z() + K.cx;
  const double v = K.fy * X_c.y() / X_c.z() + K.cy;
  if (outlier) {
    *uv = Eigen::Vector2d(rng.Uniform(0, kWidth), rng.Uniform(0, kHeight));
  } else {
    *uv = Eigen::Vector2d(u + sigma * rng.Gaussian(), v + sigma * rng.Gaussian());
  }
  // u_right from the measured u and a noisy depth (ORB-SLAM2: mvuRight = u - bf / depth). Kinect
  // depth noise ~1.4e-3 z^2 m (Khoshelham & Elberink 2012) is ~0.06 px of disparity at bf = 40;
  // 0.2 * noise_px is used (a little pessimistic).
  const double disparity = K.bf / X_c.z() + 0.2 * noise_px * rng.Gaussian();
  *u_right = stereo ? uv->x() - disparity : -1.0;
}

}  // namespace

Intrinsics SyntheticIntrinsics() {
  return Intrinsics{517.306408, 516.469215, 318.643040, 255.313989, 40.0};
}

SyntheticPoseProblem MakeSyntheticPoseProblem(const SyntheticPoseSpec& spec) {
  Rng rng(spec.seed, "optim.synthetic.pose");
  const Intrinsics K = SyntheticIntrinsics();
  SyntheticPoseProblem p;
  p.T_cw_true = MakeSE3(
      Eigen::Vector3d(0.3, -0.2, 1.1),
      Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1.0, 0.1).normalized())));
  p.T_cw_init = Perturb(p.T_cw_true, 0.03, 2.0 * M_PI / 180.0, rng);
  const SE3 T_wc = p.T_cw_true.inverse();
  for (int i = 0; i < spec.num_points; ++i) {
    const double depth = rng.Uniform(0.5, 5.0);
    const double u = rng.Uniform(0, kWidth), v = rng.Uniform(0, kHeight);
    const Eigen::Vector3d X_c((u - K.cx) / K.fx * depth, (v - K.cy) / K.fy * depth, depth);
    const int octave = static_cast<int>(rng.UniformInt(0, spec.num_octaves - 1));
    const bool outlier = rng.Bernoulli(spec.outlier_ratio);
    PoseObservation o;
    o.X_w = T_wc * X_c;
    Measure(K, X_c, octave, spec.noise_px, outlier, spec.stereo, rng, &o.uv, &o.u_right,
            &o.inv_sigma2);
    o.obs_id = "mp" + std::to_string(i) + "@f0";
    p.observations.push_back(o);
    p.is_outlier.push_back(outlier ? 1 : 0);
  }
  return p;
}

SyntheticBAProblem MakeSyntheticBAProblem(const SyntheticBASpec& spec) {
  Rng rng(spec.seed, "optim.synthetic.ba");
  const Intrinsics K = SyntheticIntrinsics();
  SyntheticBAProblem p;
  // Keyframes 10 cm apart along x, slowly yawing, looking along +z.
  for (int k = 0; k < spec.num_keyframes; ++k) {
    const Eigen::Quaterniond q_wc(Eigen::AngleAxisd(0.02 * k, Eigen::Vector3d::UnitY()));
    const SE3 T_wc = MakeSE3(Eigen::Vector3d(0.1 * k, 0.01 * k, 0.0), q_wc);
    p.T_cw_true.push_back(T_wc.inverse());
    BAKeyFrame kf;
    kf.id = 100 + k;
    kf.fixed = k < spec.num_fixed;
    kf.T_cw = kf.fixed ? p.T_cw_true.back()
                       : Perturb(p.T_cw_true.back(), spec.pose_noise_m, spec.pose_noise_rad, rng);
    p.keyframes.push_back(kf);
  }
  const int views = std::min(spec.views_per_point, spec.num_keyframes);
  for (int i = 0; i < spec.num_points; ++i) {
    const int first = static_cast<int>(rng.UniformInt(0, spec.num_keyframes - views));
    const int anchor = first + views / 2;
    const double depth = rng.Uniform(2.0, 5.0);
    const double u = rng.Uniform(40, kWidth - 40), v = rng.Uniform(40, kHeight - 40);
    const Eigen::Vector3d X_c((u - K.cx) / K.fx * depth, (v - K.cy) / K.fy * depth, depth);
    const Eigen::Vector3d X_w = p.T_cw_true[anchor].inverse() * X_c;
    p.X_w_true.push_back(X_w);
    BAPoint point;
    point.id = 1000 + i;
    point.X_w =
        X_w + spec.point_noise_m * Eigen::Vector3d(rng.Gaussian(), rng.Gaussian(), rng.Gaussian());
    p.points.push_back(point);
    for (int k = first; k < first + views; ++k) {
      const Eigen::Vector3d X_ck = p.T_cw_true[k] * X_w;
      Eigen::Vector2d uv_true;
      if (!Project(K, X_ck, &uv_true)) continue;
      const int octave = static_cast<int>(rng.UniformInt(0, 7));
      const bool outlier = rng.Bernoulli(spec.outlier_ratio);
      BAObservation o;
      o.kf_id = p.keyframes[k].id;
      o.point_id = point.id;
      Measure(K, X_ck, octave, spec.noise_px, outlier, /*stereo=*/(i % 4) != 0, rng, &o.uv,
              &o.u_right, &o.inv_sigma2);
      p.observations.push_back(o);
      p.is_outlier.push_back(outlier ? 1 : 0);
    }
  }
  return p;
}

double RmsReprojectionPx(const Intrinsics& K, const std::map<int64_t, SE3>& T_cw,
                         const std::map<int64_t, Eigen::Vector3d>& X_w,
                         const std::vector<BAObservation>& observations,
                         const std::vector<uint8_t>& mask) {
  double sum = 0;
  int count = 0;
  for (size_t i = 0; i < observations.size(); ++i) {
    if (!mask.empty() && !mask[i]) continue;
    const BAObservation& o = observations[i];
    const Eigen::Vector3d X_c = T_cw.at(o.kf_id) * X_w.at(o.point_id);
    const Eigen::Vector2d uv(K.fx * X_c.x() / X_c.z() + K.cx, K.fy * X_c.y() / X_c.z() + K.cy);
    sum += (o.uv - uv).squaredNorm();
    count += 2;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

}  // namespace dynref::optim
