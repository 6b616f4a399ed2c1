// ORB-SLAM2 LocalMapping (src/LocalMapping.cc) run sequentially; see local_mapper.h.
#include "mapping/local_mapper.h"

#include "mapping/ba_observation.h"

#include <time.h>
#include <cmath>
#include <set>

#include "core/error.h"
#include "features/descriptor.h"
#include "geometry/triangulation.h"
#include "optim/optim.h"
#include "trace/trace_writer.h"
#include "tracking/matcher.h"

namespace dynref::mapping {
namespace {

using features::RowDistance;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

// ORB-SLAM2 LocalMapping::ComputeF12.
Eigen::Matrix3d ComputeF12(const KeyFrame& k1, const KeyFrame& k2, const Camera& cam) {
  const Eigen::Matrix3d R1w = k1.T_cw.linear(), R2w = k2.T_cw.linear();
  const Eigen::Vector3d t1w = k1.T_cw.translation(), t2w = k2.T_cw.translation();
  const Eigen::Matrix3d R12 = R1w * R2w.transpose();
  const Eigen::Vector3d t12 = -R1w * R2w.transpose() * t2w + t1w;
  Eigen::Matrix3d K;
  K << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1;
  const Eigen::Matrix3d Kinv = K.inverse();
  return Kinv.transpose() * Skew(t12) * R12 * Kinv;
}

// ORB-SLAM2 ORBmatcher::CheckDistEpipolarLine.
bool CheckDistEpipolarLine(const cv::KeyPoint& kp1, const cv::KeyPoint& kp2, const Eigen::Matrix3d& F12,
                           const KeyFrame& k2) {
  const double a = kp1.pt.x * F12(0, 0) + kp1.pt.y * F12(1, 0) + F12(2, 0);
  const double b = kp1.pt.x * F12(0, 1) + kp1.pt.y * F12(1, 1) + F12(2, 1);
  const double c = kp1.pt.x * F12(0, 2) + kp1.pt.y * F12(1, 2) + F12(2, 2);
  const double num = a * kp2.pt.x + b * kp2.pt.y + c;
  const double den = a * a + b * b;
  if (den == 0) return false;
  return num * num / den < 3.84 * k2.frame.pyramid.sigma2[kp2.octave];
}

// ORB-SLAM2 ORBmatcher::SearchForTriangulation (bOnlyStereo = false) by brute force over the
// features of both keyframes that have no map point (no vocabulary; see tracking/matcher.h).
// With mnn2.enabled the descriptor rule is seed 004's MNN2 over the same candidates (mutual
// nearest, ratio rho, gate TH_HIGH equivalent), the geometric tests unchanged; every accepted pair
// is traced (stage match.mnn2.triangulation) at trace level full.
std::vector<std::pair<int, int>> SearchForTriangulation(const KeyFrame& k1, const KeyFrame& k2,
                                                        const Eigen::Matrix3d& F12, const Map& map,
                                                        const Camera& cam, const features::BackboneMnn2& mnn2,
                                                        trace::TraceWriter& trace) {
  const Eigen::Vector3d C2 = k2.T_cw * k1.CameraCentre();
  const double ex = cam.fx * C2.x() / C2.z() + cam.cx, ey = cam.fy * C2.y() / C2.z() + cam.cy;
  auto free_feature = [&](const KeyFrame& k, size_t i) {
    if (k.frame.IsExcluded(static_cast<int>(i))) return false;
    const int64_t id = k.map_point_ids[i];
    return id < 0 || map.good_mp(id) == nullptr;
  };
  std::vector<int> cand1, cand2;
  for (size_t i = 0; i < k1.N(); ++i)
    if (free_feature(k1, i)) cand1.push_back(static_cast<int>(i));
  for (size_t j = 0; j < k2.N(); ++j)
    if (free_feature(k2, j)) cand2.push_back(static_cast<int>(j));
  const cv::Mat& D1 = k1.frame.descriptors;
  const cv::Mat& D2 = k2.frame.descriptors;
  // The geometric tests of a candidate pair.
  auto geometric_ok = [&](int i, int j) {
    const cv::KeyPoint& kp2 = k2.frame.keys_un[j];
    if (k1.frame.u_right[i] < 0 && k2.frame.u_right[j] < 0) {
      const double dx = ex - kp2.pt.x, dy = ey - kp2.pt.y;
      if (dx * dx + dy * dy < 100 * k2.frame.pyramid.scale[kp2.octave]) return false;
    }
    return CheckDistEpipolarLine(k1.frame.keys_un[i], kp2, F12, k2);
  };
  std::vector<std::pair<int, int>> pairs;
  if (mnn2.enabled) {
    features::Mnn2Options o;
    o.ratio = mnn2.ratio;
    const double tau = k1.frame.match_profile.th_high;
    for (const features::Mnn2Candidate& c :
         features::SelectMnn2Candidates(features::DistanceMatrix(D1, cand1, D2, cand2), tau, o)) {
      const int i = cand1[static_cast<size_t>(c.match.i)], j = cand2[static_cast<size_t>(c.match.j)];
      const bool accepted = c.outcome == features::Mnn2Outcome::kAccepted && geometric_ok(i, j);
      if (accepted) pairs.emplace_back(i, j);
      if (!trace.full_enabled()) continue;
      // Every row MNN2 looked at (epi owns this record; ref/trace/README.md "Backbone MNN2
      // matches"): the descriptor rule's inputs and, for a row it accepted, the geometric tests'.
      double outcome = static_cast<double>(c.outcome), epipole_d2 = NAN, epipole_gate = NAN, line_d2 = NAN,
             line_gate = NAN;
      if (c.outcome == features::Mnn2Outcome::kAccepted) {
        const cv::KeyPoint& kp1 = k1.frame.keys_un[i];
        const cv::KeyPoint& kp2 = k2.frame.keys_un[j];
        if (k1.frame.u_right[i] < 0 && k2.frame.u_right[j] < 0) {
          epipole_d2 = (ex - kp2.pt.x) * (ex - kp2.pt.x) + (ey - kp2.pt.y) * (ey - kp2.pt.y);
          epipole_gate = 100 * k2.frame.pyramid.scale[kp2.octave];
        }
        const double a = kp1.pt.x * F12(0, 0) + kp1.pt.y * F12(1, 0) + F12(2, 0);
        const double b = kp1.pt.x * F12(0, 1) + kp1.pt.y * F12(1, 1) + F12(2, 1);
        const double cc = kp1.pt.x * F12(0, 2) + kp1.pt.y * F12(1, 2) + F12(2, 2);
        const double num = a * kp2.pt.x + b * kp2.pt.y + cc, den = a * a + b * b;
        line_d2 = den == 0 ? INFINITY : num * num / den;
        line_gate = 3.84 * k2.frame.pyramid.sigma2[kp2.octave];
        if (!accepted) outcome = tracking::kMnn2OutcomeGeometry;
      }
      std::vector<trace::NamedValue> in = tracking::Mnn2TraceInputs(
          c.match, tau, {{"kf", double(k1.id)}, {"kf_feature", double(i)}, {"kf2", double(k2.id)}});
      in.push_back({"rho", mnn2.ratio});
      in.push_back({"second_feature", c.second_j < 0 ? -1.0 : double(cand2[static_cast<size_t>(c.second_j)])});
      in.push_back({"reverse_kf_feature", double(cand1[static_cast<size_t>(c.reverse_i)])});
      in.push_back({"reverse_distance", c.reverse_distance});
      in.push_back({"epipole_d2", epipole_d2});
      in.push_back({"epipole_gate", epipole_gate});
      in.push_back({"line_d2", line_d2});
      in.push_back({"line_gate", line_gate});
      in.push_back({"outcome", outcome});
      trace.ProbabilityUpdate("match.mnn2.triangulation", trace::EntityKind::kFeature, k2.frame.FeatureId(j), in,
                              0.0, 0.0);
    }
    return pairs;
  }
  const float th_low = k1.frame.match_profile.th_low;
  std::vector<int> matched2(k2.N(), -1);
  for (int i : cand1) {
    float best_dist = th_low;
    int best_idx = -1;
    for (int j : cand2) {
      if (matched2[j] >= 0) continue;
      const float dist = RowDistance(D1, i, D2, j);
      if (dist > th_low || dist > best_dist) continue;
      if (geometric_ok(i, j)) {
        best_idx = j;
        best_dist = dist;
      }
    }
    if (best_idx >= 0) {
      matched2[best_idx] = i;
      pairs.emplace_back(i, best_idx);
    }
  }
  // No rotation-consistency check: LocalMapping::CreateNewMapPoints builds its matcher with
  // checkOri = false (ORBmatcher matcher(0.6, false)).
  return pairs;
}

}  // namespace

void LocalMapperOptions::Check() const {
  if (covisible_for_triangulation < 1) throw InputError("local mapper options", "covisible_for_triangulation must be >= 1");
  if (!(redundancy > 0 && redundancy <= 1)) throw InputError("local mapper options", "redundancy must be in (0, 1]");
  ba.Check();
}

LocalMapper::LocalMapper(Map& map, const Camera& camera, const LocalMapperOptions& options, trace::TraceWriter& trace)
    : map_(map), camera_(camera), options_(options), trace_(trace) {
  options_.Check();
}

void LocalMapper::ProcessNewKeyFrame(KeyFrame& kf) {
  for (size_t i = 0; i < kf.N(); ++i) {
    const int64_t id = kf.map_point_ids[i];
    if (id < 0) continue;
    MapPoint* p = map_.good_mp(id);
    if (p == nullptr || kf.frame.IsExcluded(static_cast<int>(i))) {
      // Excluded by a kOnKeyFrameCreated stage after tracking made the point: drop the link.
      if (p != nullptr) map_.EraseObservation(id, kf.id);
      kf.map_point_ids[i] = -1;
      continue;
    }
    auto it = p->observations.find(kf.id);
    if (it == p->observations.end()) {
      map_.AddObservation(id, kf.id, static_cast<int>(i));
      map_.UpdatePointNormalAndDepth(id);
      map_.UpdatePointDescriptor(id);
    } else if (it->second == static_cast<int>(i)) {
      recent_points_.push_back(id);  // created by tracking for this keyframe
    } else {
      kf.map_point_ids[i] = -1;      // the same point matched twice: keep the first observation
    }
  }
  map_.UpdateConnections(kf.id);
}

int LocalMapper::MapPointCulling(const KeyFrame& kf) {
  const int cn_th_obs = 3;
  int culled = 0;
  std::vector<int64_t> keep;
  for (int64_t id : recent_points_) {
    MapPoint* p = map_.mp(id);
    if (p == nullptr || p->bad) continue;
    if (p->FoundRatio() < 0.25) {
      map_.SetBadPoint(id);
      ++culled;
    } else if (kf.id - p->first_kf >= 2 && p->n_obs <= cn_th_obs) {
      map_.SetBadPoint(id);
      ++culled;
    } else if (kf.id - p->first_kf >= 3) {
      // old enough: leaves the recent list
    } else {
      keep.push_back(id);
    }
  }
  recent_points_ = keep;
  return culled;
}

int LocalMapper::CreateNewMapPoints(KeyFrame& kf) {
  const std::vector<int64_t> neighbours = kf.BestCovisibles(options_.covisible_for_triangulation);
  const Eigen::Vector3d O1 = kf.CameraCentre();
  const double ratio_factor = 1.5 * kf.frame.pyramid.scale_factor;
  const Camera& cam = camera_;
  int created = 0;
  for (int64_t n_id : neighbours) {
    KeyFrame* k2 = map_.kf(n_id);
    if (k2 == nullptr || k2->bad) continue;
    const Eigen::Vector3d O2 = k2->CameraCentre();
    if ((O2 - O1).norm() < cam.baseline_m()) continue;
    const Eigen::Matrix3d F12 = ComputeF12(kf, *k2, cam);
    const auto matches = SearchForTriangulation(kf, *k2, F12, map_, cam, options_.mnn2, trace_);
    const Eigen::Matrix<double, 3, 4> P1 = kf.T_cw.matrix().topRows<3>();
    const Eigen::Matrix<double, 3, 4> P2 = k2->T_cw.matrix().topRows<3>();
    for (const auto& [i1, i2] : matches) {
      const cv::KeyPoint& kp1 = kf.frame.keys_un[i1];
      const cv::KeyPoint& kp2 = k2->frame.keys_un[i2];
      const double ur1 = kf.frame.u_right[i1], ur2 = k2->frame.u_right[i2];
      const bool stereo1 = ur1 >= 0, stereo2 = ur2 >= 0;
      const Eigen::Vector3d xn1((kp1.pt.x - cam.cx) / cam.fx, (kp1.pt.y - cam.cy) / cam.fy, 1.0);
      const Eigen::Vector3d xn2((kp2.pt.x - cam.cx) / cam.fx, (kp2.pt.y - cam.cy) / cam.fy, 1.0);
      const Eigen::Vector3d ray1 = kf.T_cw.linear().transpose() * xn1;
      const Eigen::Vector3d ray2 = k2->T_cw.linear().transpose() * xn2;
      const double cos_rays = ray1.dot(ray2) / (ray1.norm() * ray2.norm());
      // ORB-SLAM2 LocalMapping::CreateNewMapPoints computes the stereo parallax of the second
      // keyframe only when the current keyframe's feature has no depth: with depth in both, the
      // current keyframe's parallax decides and its depth is used when the rays are too close.
      double cos_stereo1 = cos_rays + 1, cos_stereo2 = cos_rays + 1;
      if (stereo1) cos_stereo1 = std::cos(2 * std::atan2(cam.baseline_m() / 2, kf.frame.depth[i1]));
      else if (stereo2) cos_stereo2 = std::cos(2 * std::atan2(cam.baseline_m() / 2, k2->frame.depth[i2]));
      const double cos_stereo = std::min(cos_stereo1, cos_stereo2);
      Eigen::Vector3d X;
      if (cos_rays < cos_stereo && cos_rays > 0 && (stereo1 || stereo2 || cos_rays < 0.9998)) {
        if (!geometry::TriangulateLinear(P1, P2, xn1.head<2>(), xn2.head<2>(), &X)) continue;
      } else if (stereo1 && cos_stereo1 < cos_stereo2) {
        X = kf.frame.UnprojectWorld(i1);
      } else if (stereo2 && cos_stereo2 < cos_stereo1) {
        X = k2->frame.UnprojectWorld(i2);
      } else {
        continue;
      }
      const Eigen::Vector3d Xc1 = kf.T_cw * X, Xc2 = k2->T_cw * X;
      if (Xc1.z() <= 0 || Xc2.z() <= 0) continue;
      // Reprojection errors (chi2 5.991 mono / 7.8 stereo, ORB-SLAM2).
      auto reproj_ok = [&](const Eigen::Vector3d& Xc, const cv::KeyPoint& kp, double ur, bool stereo,
                           const ScalePyramid& pyr) {
        const double sigma2 = pyr.sigma2[kp.octave];
        const double u = cam.fx * Xc.x() / Xc.z() + cam.cx, v = cam.fy * Xc.y() / Xc.z() + cam.cy;
        const double ex = u - kp.pt.x, ey = v - kp.pt.y;
        if (!stereo) return ex * ex + ey * ey <= 5.991 * sigma2;
        const double er = u - cam.bf / Xc.z() - ur;
        return ex * ex + ey * ey + er * er <= 7.8 * sigma2;
      };
      if (!reproj_ok(Xc1, kp1, ur1, stereo1, kf.frame.pyramid)) continue;
      if (!reproj_ok(Xc2, kp2, ur2, stereo2, k2->frame.pyramid)) continue;
      // Scale consistency.
      const double d1 = (X - O1).norm(), d2 = (X - O2).norm();
      if (d1 == 0 || d2 == 0) continue;
      const double ratio_dist = d2 / d1;
      const double ratio_octave = kf.frame.pyramid.scale[kp1.octave] / k2->frame.pyramid.scale[kp2.octave];
      if (ratio_dist * ratio_factor < ratio_octave || ratio_dist > ratio_octave * ratio_factor) continue;
      MapPoint* p = map_.NewMapPoint(X, kf.id, kf.frame_index);
      map_.AddObservation(p->id, kf.id, i1);
      map_.AddObservation(p->id, k2->id, i2);
      map_.UpdatePointDescriptor(p->id);
      map_.UpdatePointNormalAndDepth(p->id);
      recent_points_.push_back(p->id);
      ++created;
    }
  }
  return created;
}

int LocalMapper::Fuse(KeyFrame& target, const std::vector<int64_t>& points, float th) {
  // ORB-SLAM2 ORBmatcher::Fuse(KeyFrame*, vector<MapPoint*>, th).
  const Camera& cam = camera_;
  const Eigen::Vector3d O = target.CameraCentre();
  const ScalePyramid& pyr = target.frame.pyramid;
  int fused = 0;
  for (int64_t id : points) {
    MapPoint* p = map_.good_mp(id);
    if (p == nullptr || p->observations.count(target.id)) continue;
    const Eigen::Vector3d Xc = target.T_cw * p->X_w;
    if (Xc.z() < 0) continue;
    const double invz = 1.0 / Xc.z();
    const double u = cam.fx * Xc.x() * invz + cam.cx, v = cam.fy * Xc.y() * invz + cam.cy;
    if (!target.frame.InImage(static_cast<float>(u), static_cast<float>(v))) continue;
    const double ur = u - cam.bf * invz;
    const Eigen::Vector3d PO = p->X_w - O;
    const double dist = PO.norm();
    if (dist < 0.8 * p->min_distance || dist > 1.2 * p->max_distance) continue;
    if (PO.dot(p->normal) < 0.5 * dist) continue;
    const int level = p->PredictScale(static_cast<float>(dist), pyr);
    const float radius = th * pyr.scale[level];
    const std::vector<int> idx = target.frame.FeaturesInArea(static_cast<float>(u), static_cast<float>(v), radius);
    float best_dist = target.frame.match_profile.worst;
    int best_idx = -1;
    for (int j : idx) {
      const cv::KeyPoint& kp = target.frame.keys_un[j];
      if (kp.octave < level - 1 || kp.octave > level) continue;
      const double ex = u - kp.pt.x, ey = v - kp.pt.y;
      if (target.frame.u_right[j] >= 0) {
        const double er = ur - target.frame.u_right[j];
        if ((ex * ex + ey * ey + er * er) * pyr.inv_sigma2[kp.octave] > 7.8) continue;
      } else if ((ex * ex + ey * ey) * pyr.inv_sigma2[kp.octave] > 5.99) {
        continue;
      }
      const float d = RowDistance(p->descriptor, 0, target.frame.descriptors, j);
      if (d < best_dist) {
        best_dist = d;
        best_idx = j;
      }
    }
    if (best_idx < 0 || best_dist > target.frame.match_profile.th_low) continue;
    const int64_t in_kf = target.map_point_ids[best_idx];
    const MapPoint* q = in_kf >= 0 ? map_.good_mp(in_kf) : nullptr;
    if (q != nullptr) {
      if (q->n_obs > p->n_obs) map_.ReplacePoint(p->id, q->id);
      else map_.ReplacePoint(q->id, p->id);
    } else {
      map_.AddObservation(p->id, target.id, best_idx);
    }
    ++fused;
  }
  return fused;
}

int LocalMapper::SearchInNeighbors(KeyFrame& kf) {
  std::vector<int64_t> targets;
  for (int64_t n : kf.BestCovisibles(options_.covisible_for_triangulation)) {
    KeyFrame* k = map_.kf(n);
    if (k == nullptr || k->bad || k->fuse_target_kf == kf.id) continue;
    targets.push_back(n);
    k->fuse_target_kf = static_cast<int>(kf.id);
    for (int64_t n2 : k->BestCovisibles(5)) {
      KeyFrame* k2 = map_.kf(n2);
      if (k2 == nullptr || k2->bad || k2->fuse_target_kf == kf.id || n2 == kf.id) continue;
      targets.push_back(n2);
    }
  }
  int fused = 0;
  std::vector<int64_t> own;
  for (int64_t id : kf.map_point_ids)
    if (id >= 0 && map_.good_mp(id) != nullptr) own.push_back(id);
  for (int64_t t : targets) fused += Fuse(*map_.kf(t), own, 3.0f);
  std::vector<int64_t> candidates;
  for (int64_t t : targets) {
    for (int64_t id : map_.kf(t)->map_point_ids) {
      MapPoint* p = id >= 0 ? map_.good_mp(id) : nullptr;
      if (p == nullptr || p->fuse_candidate_kf == kf.id) continue;
      p->fuse_candidate_kf = kf.id;
      candidates.push_back(id);
    }
  }
  fused += Fuse(kf, candidates, 3.0f);
  for (int64_t id : kf.map_point_ids) {
    if (id < 0 || map_.good_mp(id) == nullptr) continue;
    map_.UpdatePointDescriptor(id);
    map_.UpdatePointNormalAndDepth(id);
  }
  map_.UpdateConnections(kf.id);
  return fused;
}

int LocalMapper::LocalBundleAdjustment(KeyFrame& kf, LocalMapperStats* stats) {
  // ORB-SLAM2 Optimizer::LocalBundleAdjustment: the keyframe and its covisibles are free
  // (keyframe 0 fixed), keyframes observing their points but outside are fixed.
  std::set<int64_t> local{kf.id};
  for (int64_t id : kf.ordered_covisibles) {
    const KeyFrame* k = map_.kf(id);
    if (k != nullptr && !k->bad) local.insert(id);
  }
  std::set<int64_t> points, fixed;
  for (int64_t k_id : local)
    for (int64_t id : map_.kf(k_id)->map_point_ids)
      if (id >= 0 && map_.good_mp(id) != nullptr) points.insert(id);
  for (int64_t id : points)
    for (const auto& kv : map_.mp(id)->observations)
      if (!local.count(kv.first) && !map_.kf(kv.first)->bad) fixed.insert(kv.first);
  optim::LocalBAStructure structure;
  if (structure_ != nullptr) structure_->FillLocalBA(map_, local, &fixed, &structure);
  std::vector<optim::BAKeyFrame> kfs;
  for (int64_t id : local) kfs.push_back({id, map_.kf(id)->T_cw, id == 0});
  for (int64_t id : fixed) kfs.push_back({id, map_.kf(id)->T_cw, true});
  std::vector<optim::BAPoint> pts;
  std::vector<optim::BAObservation> obs;
  for (int64_t id : points) {
    const MapPoint* p = map_.mp(id);
    pts.push_back({id, p->X_w});
    for (const auto& [k_id, idx] : p->observations) {
      const KeyFrame* k = map_.kf(k_id);
      if (k->bad || (!local.count(k_id) && !fixed.count(k_id))) continue;
      if (k->frame.IsExcluded(idx)) continue;
      obs.push_back(KeyframeObservation(*k, k_id, id, idx));
    }
  }
  ++ba_calls_;
  stats->ba_keyframes = static_cast<int>(kfs.size());
  stats->ba_points = static_cast<int>(pts.size());
  stats->ba_observations =
      static_cast<int>(obs.size() + structure.line_observations.size() + structure.plane_observations.size());
  const Intrinsics K = camera_.Pinhole();
  timespec c0{}, c1{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);  // CPU time of this (single) thread
  // Concurrent variant: tracking goes on while Ceres solves the copied problem; the lock is held
  // again (also when the solve throws) before the result is written back.
  struct Unlocked {
    std::unique_lock<std::mutex>* lock;
    explicit Unlocked(std::unique_lock<std::mutex>* l) : lock(l) { if (lock != nullptr) lock->unlock(); }
    ~Unlocked() { if (lock != nullptr) lock->lock(); }
  };
  optim::LocalBAResult r;
  {
    const Unlocked unlocked(map_lock_);
    r = optim::LocalBundleAdjust(K, kfs, pts, obs, structure_ != nullptr ? &structure : nullptr, options_.ba, &trace_,
                                 "localba#" + std::to_string(ba_calls_));
  }
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
  stats->ba_ms = (c1.tv_sec - c0.tv_sec) * 1e3 + (c1.tv_nsec - c0.tv_nsec) * 1e-6;
  int outliers = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    if (r.inlier[i]) continue;
    map_.EraseObservation(obs[i].point_id, obs[i].kf_id);
    ++outliers;
  }
  if (structure_ != nullptr) outliers += structure_->ApplyLocalBA(map_, structure, r);
  for (int64_t id : local) {
    KeyFrame* k = map_.kf(id);
    auto it = r.T_cw.find(id);
    if (it != r.T_cw.end() && id != 0) k->T_cw = it->second;
  }
  for (int64_t id : points) {
    MapPoint* p = map_.mp(id);
    if (p->bad) continue;
    auto it = r.X_w.find(id);
    if (it != r.X_w.end()) p->X_w = it->second;
    map_.UpdatePointNormalAndDepth(id);
  }
  return outliers;
}

int LocalMapper::KeyFrameCulling(const KeyFrame& kf) {
  const double th_depth_m = camera_.th_depth * camera_.baseline_m();
  const int th_obs = 3;
  int culled = 0;
  const std::vector<int64_t> covisibles = kf.ordered_covisibles;
  for (int64_t k_id : covisibles) {
    const KeyFrame* k = map_.kf(k_id);
    // A keyframe without a spanning-tree parent (no shared points when it was connected) is
    // never culled: its trajectory frames could not be re-anchored (ORB-SLAM2 would dereference
    // a null parent in KeyFrame::SetBadFlag).
    if (k == nullptr || k->bad || k_id == 0 || k->parent < 0) continue;
    int n_mps = 0, redundant = 0;
    for (size_t i = 0; i < k->N(); ++i) {
      const int64_t id = k->map_point_ids[i];
      const MapPoint* p = id >= 0 ? map_.good_mp(id) : nullptr;
      if (p == nullptr) continue;
      if (k->frame.depth[i] > th_depth_m || k->frame.depth[i] < 0) continue;
      ++n_mps;
      if (p->n_obs <= th_obs) continue;
      const int level = k->frame.keys_un[i].octave;
      int n = 0;
      for (const auto& [o_id, idx] : p->observations) {
        if (o_id == k_id) continue;
        if (map_.kf(o_id)->frame.keys_un[idx].octave <= level + 1 && ++n >= th_obs) break;
      }
      if (n >= th_obs) ++redundant;
    }
    if (redundant > options_.redundancy * n_mps) {
      map_.SetBadKeyFrame(k_id);
      ++culled;
    }
  }
  return culled;
}

LocalMapperStats LocalMapper::ProcessKeyFrame(int64_t kf_id) {
  LocalMapperStats s;
  KeyFrame& kf = *map_.kf(kf_id);
  ProcessNewKeyFrame(kf);
  s.culled_points = MapPointCulling(kf);
  s.new_points = CreateNewMapPoints(kf);
  s.fused = SearchInNeighbors(kf);
  if (options_.local_ba && map_.keyframes.size() > 2) s.ba_outliers = LocalBundleAdjustment(kf, &s);
  if (options_.keyframe_culling) s.culled_keyframes = KeyFrameCulling(kf);
  if (structure_ != nullptr) {
    std::set<int64_t> local{kf.id};
    for (int64_t id : kf.ordered_covisibles) local.insert(id);
    structure_->MaintainMap(map_, kf.id, local);
  }
  trace_.FrameCount("mapping", "culled_points", s.culled_points);
  trace_.FrameCount("mapping", "new_points", s.new_points);
  trace_.FrameCount("mapping", "fused", s.fused);
  trace_.FrameCount("mapping", "ba_outliers", s.ba_outliers);
  trace_.FrameCount("mapping", "culled_keyframes", s.culled_keyframes);
  trace_.FrameCount("mapping", "ba_observations", s.ba_observations);
  return s;
}

}  // namespace dynref::mapping
