// ORB-SLAM2 Tracking::Relocalization with dynref substitutes: candidates are the most recent
// keyframes or the keyframe database's (backbone.relocalisation, relocaliser_bow.h), keyframe-to-
// frame matching is brute force (matcher.h) or by vocabulary node (backbone.bow_matching), and the
// PnP RANSAC is ours (EPnP on minimal sets of 4 drawn from the seeded stream "tracking.reloc",
// ORB-SLAM2 PnPsolver parameters 0.99 / 10 / 300 / 4 / 0.5 / 5.991) so that no library RNG is
// involved.
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include "tracking/matcher.h"
#include "tracking/relocaliser_bow.h"
#include "tracking/tracker.h"

namespace dynref::tracking {
namespace {

bool SolveEpnp(const std::vector<cv::Point3d>& X, const std::vector<cv::Point2d>& uv, const Camera& cam,
               SE3* T_cw) {
  cv::Mat rvec, tvec;
  const cv::Mat K(cam.K());
  bool ok = false;
  try {
    ok = cv::solvePnP(X, uv, K, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_EPNP);
  } catch (const cv::Exception&) {
    return false;
  }
  if (!ok) return false;
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) Re(r, c) = R.at<double>(r, c);
    te(r) = tvec.at<double>(r);
  }
  if (!Re.allFinite() || !te.allFinite()) return false;
  T_cw->setIdentity();
  T_cw->linear() = Re;
  T_cw->translation() = te;
  return true;
}

// EPnP on the correspondences ks (positions in idx / X), in that order.
bool SolveEpnpOn(const Frame& f, const Camera& cam, const std::vector<int>& idx, const std::vector<Eigen::Vector3d>& X,
                 const std::vector<int>& ks, SE3* T_cw) {
  std::vector<cv::Point3d> Xs;
  std::vector<cv::Point2d> us;
  for (int k : ks) {
    Xs.emplace_back(X[k].x(), X[k].y(), X[k].z());
    us.emplace_back(f.keys_un[idx[k]].pt.x, f.keys_un[idx[k]].pt.y);
  }
  return SolveEpnp(Xs, us, cam, T_cw);
}

// Inliers of pose T: in front of the camera and reprojected within the chi2 gate 5.991 (ORB-SLAM2
// PnPsolver) scaled by the key's level. Returns their count; inl: a flag per correspondence.
int ScoreRelocPose(const Frame& f, const Camera& cam, const std::vector<int>& idx, const std::vector<Eigen::Vector3d>& X,
                   const SE3& T, std::vector<uint8_t>* inl) {
  const double th2 = 5.991;
  const int n = static_cast<int>(idx.size());
  int c = 0;
  inl->assign(n, 0);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d Xc = T * X[k];
    if (Xc.z() <= 0) continue;
    const Eigen::Vector2d p = ProjectPinhole(cam, Xc);
    const cv::KeyPoint& kp = f.keys_un[idx[k]];
    const double e2 = (p - Eigen::Vector2d(kp.pt.x, kp.pt.y)).squaredNorm();
    if (e2 < th2 * f.pyramid.sigma2[kp.octave]) {
      (*inl)[k] = 1;
      ++c;
    }
  }
  return c;
}

// Four distinct correspondences drawn from the stream.
std::vector<int> DrawPnpSample(Rng& rng, int n) {
  std::vector<int> sample;
  while (sample.size() < 4) {
    const int s = static_cast<int>(rng.UniformInt(0, n - 1));
    if (std::find(sample.begin(), sample.end(), s) == sample.end()) sample.push_back(s);
  }
  return sample;
}

void DropRelocOutliers(Frame& f) {
  for (size_t i = 0; i < f.N(); ++i)
    if (f.outlier[i]) {
      f.map_point_ids[i] = -1;
      f.outlier[i] = 0;
    }
}

std::set<int64_t> RelocFoundPoints(const Frame& f) {
  std::set<int64_t> s;
  for (int64_t id : f.map_point_ids)
    if (id >= 0) s.insert(id);
  return s;
}

}  // namespace

bool Tracker::PnpRansac(const Frame& f, const std::vector<int>& idx, const std::vector<Eigen::Vector3d>& X,
                        SE3* T_cw, std::vector<uint8_t>* inliers) {
  const int n = static_cast<int>(idx.size());
  if (n < 4) return false;
  // ORB-SLAM2 PnPsolver::SetRansacParameters(0.99, 10, 300, 4, 0.5, 5.991).
  const double probability = 0.99, epsilon = 0.5;
  const int min_inliers = std::max(10, static_cast<int>(n * epsilon));
  int iterations = options_.ransac_iterations;
  if (min_inliers != n) {
    const double it = std::ceil(std::log(1 - probability) / std::log(1 - std::pow(static_cast<double>(min_inliers) / n, 3)));
    iterations = std::max(1, std::min(iterations, static_cast<int>(it)));
  }
  int best = -1;
  std::vector<uint8_t> best_inl;
  SE3 best_T = SE3::Identity();
  for (int it = 0; it < iterations; ++it) {
    SE3 T;
    if (!SolveEpnpOn(f, camera_, idx, X, DrawPnpSample(rng_, n), &T)) continue;
    std::vector<uint8_t> inl;
    const int c = ScoreRelocPose(f, camera_, idx, X, T, &inl);
    if (c > best) {
      best = c;
      best_inl = inl;
      best_T = T;
    }
  }
  if (best < min_inliers) return false;
  // Refine with all inliers (ORB-SLAM2 PnPsolver::Refine), keep it when it does not lose inliers.
  std::vector<int> inlier_ks;
  for (int k = 0; k < n; ++k)
    if (best_inl[k]) inlier_ks.push_back(k);
  SE3 T_ref;
  if (SolveEpnpOn(f, camera_, idx, X, inlier_ks, &T_ref)) {
    std::vector<uint8_t> inl;
    if (ScoreRelocPose(f, camera_, idx, X, T_ref, &inl) >= best) {
      best_T = T_ref;
      best_inl = inl;
    }
  }
  *T_cw = best_T;
  *inliers = best_inl;
  return true;
}

// ORB-SLAM2 Tracking::Relocalization after the PnP pose: with fewer than 50 inliers, points of
// the candidate keyframe found by projection (window 10, then 3) and the pose optimised again.
int Tracker::RelocaliseByProjection(Frame& f, const KeyFrame& kf, int good) {
  const int add = SearchByProjectionKeyFrame(f, kf, map_, RelocFoundPoints(f), 10, f.match_profile.th_high);
  if (add + good < 50) return good;
  good = OptimizePose(f);
  if (good > 30 && good < 50) {
    DropRelocOutliers(f);
    const int add2 = SearchByProjectionKeyFrame(f, kf, map_, RelocFoundPoints(f), 3, f.match_profile.th_reloc);
    if (good + add2 >= 50) good = OptimizePose(f);
  }
  DropRelocOutliers(f);
  return good;
}

// The candidate's matches, PnP RANSAC and pose optimisation; true with >= 50 inliers. Each
// candidate leaves its keyframe and how far it got (track.reloc candidate_*: matches, PnP
// inliers, optimised inliers; -1 = that step was not reached).
bool Tracker::RelocaliseFrom(Frame& f, const KeyFrame& kf, const PlaceBow& frame_bow) {
  int n = -1, pnp = -1, good = -1;
  const bool ok = RelocaliseSteps(f, kf, frame_bow, &n, &pnp, &good);
  trace_.FrameCount("track.reloc", "candidate_kf", kf.id);
  trace_.FrameCount("track.reloc", "candidate_matches", n);
  trace_.FrameCount("track.reloc", "candidate_pnp_inliers", pnp);
  trace_.FrameCount("track.reloc", "candidate_inliers", good);
  if (!ok) return false;
  last_reloc_frame_ = f.index;
  trace_.FrameCount("track.reloc", "inliers", good);
  return true;
}

bool Tracker::RelocaliseSteps(Frame& f, const KeyFrame& kf, const PlaceBow& frame_bow, int* n_matches, int* n_pnp,
                              int* n_good) {
  std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  const int n = *n_matches = MatchRelocalisationCandidate(kf, f, map_, options_, place_, frame_bow);
  if (n < 15) return false;
  std::vector<int> idx;
  std::vector<Eigen::Vector3d> X;
  for (size_t i = 0; i < f.N(); ++i) {
    if (f.map_point_ids[i] < 0) continue;
    idx.push_back(static_cast<int>(i));
    X.push_back(map_.mp(f.map_point_ids[i])->X_w);
  }
  SE3 T;
  std::vector<uint8_t> inl;
  const bool found = PnpRansac(f, idx, X, &T, &inl);
  *n_pnp = found ? static_cast<int>(std::count(inl.begin(), inl.end(), uint8_t{1})) : 0;
  if (!found) return false;
  for (size_t k = 0; k < idx.size(); ++k)
    if (!inl[k]) f.map_point_ids[idx[k]] = -1;
  f.T_cw = T;
  int good = *n_good = OptimizePose(f);
  if (good < 10) return false;
  DropRelocOutliers(f);
  if (good < 50) good = *n_good = RelocaliseByProjection(f, kf, good);
  return good >= 50;
}

bool Tracker::Relocalise(Frame& f) {
  PlaceBow frame_bow;  // the frame's vectors when a vocabulary is used (relocaliser_bow.h)
  const std::vector<int64_t> candidates = RelocalisationCandidates(f, map_, options_, place_, trace_, &frame_bow);
  for (int64_t kf_id : candidates)
    if (RelocaliseFrom(f, *map_.kf(kf_id), frame_bow)) return true;
  std::fill(f.map_point_ids.begin(), f.map_point_ids.end(), -1);
  return false;
}

}  // namespace dynref::tracking
