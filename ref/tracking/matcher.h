// ORB-SLAM2 ORBmatcher equivalents on dynref Frame / KeyFrame / Map. ORB-SLAM2 restricts
// keyframe-to-frame matching to features sharing a DBoW2 vocabulary node; dynref has no
// vocabulary and matches by brute force over all candidate pairs with the same distance
// threshold (TH_LOW), ratio test and rotation-consistency histogram (issue 5, item 3).
// Excluded features (Frame::Exclude) are never candidates.
#pragma once
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "features/mnn2.h"
#include "map/frame.h"
#include "map/map.h"
#include "trace/trace_writer.h"

namespace dynref::tracking {

// Pinhole projection of a camera-frame point (undistorted pixels).
inline Eigen::Vector2d ProjectPinhole(const Camera& cam, const Eigen::Vector3d& X_c) {
  return {cam.fx * X_c.x() / X_c.z() + cam.cx, cam.fy * X_c.y() / X_c.z() + cam.cy};
}

// A local map point prepared for projection search (ORB-SLAM2 MapPoint::mbTrackInView & co).
struct ProjectedPoint {
  int64_t mp_id = -1;
  float u = 0, v = 0, u_right = 0;
  int predicted_level = 0;
  float view_cos = 0;
};

// ORB-SLAM2 Frame::isInFrustum(pMP, 0.5).
bool IsInFrustum(const Frame& f, const MapPoint& p, ProjectedPoint* out);

// Motion-model search (ORBmatcher::SearchByProjection(Frame&, const Frame&, th, bMono=false),
// with orientation check): projects the last frame's inlier map points into the current frame.
int SearchByProjectionLastFrame(Frame& cur, const Frame& last, const Map& map, float th);

// Local-map search (ORBmatcher::SearchByProjection(Frame&, vector<MapPoint*>, th), ratio 0.8).
int SearchByProjectionLocal(Frame& cur, const std::vector<ProjectedPoint>& points, const Map& map,
                            float th, float nn_ratio = 0.8f);

// Replacement for ORBmatcher::SearchByBoW(KeyFrame*, Frame&): brute force, best distance <=
// TH_LOW, best < ratio * second best, first-come one-to-one, rotation histogram. Writes the
// matched map point ids into cur.map_point_ids; returns the number of matches.
// With mnn2.enabled: seed 004's MNN2 instead (features/mnn2.h BackboneMnn2). At trace level full
// every row the rule looked at is traced as PROB `mnn2_stage` (match.mnn2.reference from
// reference-keyframe tracking, match.mnn2.relocalisation from relocalisation) on its nearest
// frame feature, p = 0, with the outcome (kMnn2Outcome*; ref/trace/README.md). Distances and
// gates in the frame's match_profile units; the rotation check only for oriented extractors.
int SearchByBruteForce(const KeyFrame& kf, Frame& cur, const Map& map, float nn_ratio,
                       bool check_orientation, const features::BackboneMnn2& mnn2 = {},
                       const std::string& mnn2_stage = "match.mnn2.reference");

// Input `outcome` of the MNN2 trace records: features::Mnn2Outcome (0 accepted, 1 tau, 2 ratio,
// 3 not mutual), then the tests after the descriptor rule: 4 the rotation check (tracking),
// 5 the epipolar / epipole test (triangulation search).
constexpr double kMnn2OutcomeRotation = 4;
constexpr double kMnn2OutcomeGeometry = 5;

// Trace inputs of one MNN2 match: `ids` first, then distance, second, ratio = distance / second
// (0 when second is 0) and tau (the match.mnn2 records, ref/trace/README.md).
std::vector<trace::NamedValue> Mnn2TraceInputs(const features::DescriptorMatch& m, double tau,
                                               std::vector<trace::NamedValue> ids);

// ORBmatcher::SearchByProjection(Frame&, KeyFrame*, set<MapPoint*> sAlreadyFound, th, ORBdist)
// used by relocalisation.
// max_dist in the frame's match_profile units (ORB-SLAM2: 100, then 64 bits).
int SearchByProjectionKeyFrame(Frame& cur, const KeyFrame& kf, const Map& map,
                               const std::set<int64_t>& already_found, float th, float max_dist);

}  // namespace dynref::tracking
