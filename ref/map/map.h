// Keyframes, map points, covisibility graph (ORB-SLAM2 KeyFrame / MapPoint / Map). Every
// container is keyed by id (std::map) and iterated in id order: no pointer-ordered sets.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/se3.h"
#include "map/frame.h"
#include "map/landmark.h"
#include "map/structure.h"

namespace dynref {

class MapPoint {
 public:
  int64_t id = -1;
  Eigen::Vector3d X_w = Eigen::Vector3d::Zero();
  std::map<int64_t, int> observations;  // keyframe id -> keypoint index in that keyframe
  int n_obs = 0;  // ORB-SLAM2 Observations(): an RGB-D (u_right >= 0) observation counts 2
  cv::Mat descriptor;                   // 1 row of the frames' type, the most representative (ORB-SLAM2)
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // mean viewing direction
  float min_distance = 0, max_distance = 0;          // scale invariance distances
  int64_t ref_kf = -1;          // reference keyframe id
  int64_t first_kf = -1;        // keyframe that created it
  int first_frame = -1;         // frame index that created it
  int visible = 1, found = 1;   // ORB-SLAM2 mnVisible / mnFound
  bool bad = false;
  int64_t replaced_by = -1;
  LandmarkDynamicState dynamic;  // a method's p(dynamic) of this point (landmark.h)
  // tracking scratch (ORB-SLAM2 mnTrackReferenceForFrame, mnLastFrameSeen, projection)
  int track_ref_frame = -1, last_seen_frame = -1;
  int64_t fuse_candidate_kf = -1;
  double FoundRatio() const { return static_cast<double>(found) / visible; }
  int PredictScale(float distance, const ScalePyramid& pyr) const;
};

class KeyFrame {
 public:
  int64_t id = -1;
  int frame_index = -1;
  double stamp = 0;
  std::string stamp_text;
  SE3 T_cw = SE3::Identity();

  // Copied from the frame (kept so stages can read them: SGDO needs depth + rgb of the ref KF).
  Frame frame;                           // keys, descriptors, depth, u_right, weights, rgb, depth_m
  std::vector<int64_t> map_point_ids;    // per key, -1 none

  // Covisibility: weights to other keyframes (shared map points), id ordered.
  std::map<int64_t, int> connections;
  std::vector<int64_t> ordered_covisibles;  // by weight desc, id asc tie-break
  int64_t parent = -1;
  SE3 T_cp = SE3::Identity();  // camera from parent, stored when set bad (ORB-SLAM2 mTcp)
  bool bad = false;
  bool not_erase = false;
  // local mapping / tracking scratch
  int track_ref_frame = -1, fuse_target_kf = -1, ba_local_kf = -1, ba_fixed_kf = -1;

  size_t N() const { return frame.N(); }
  Eigen::Vector3d CameraCentre() const { return T_cw.inverse().translation(); }
  std::vector<int64_t> BestCovisibles(int n) const;
  std::vector<int64_t> CovisiblesWithWeight(int w) const;
  int TrackedMapPoints(int min_obs, const class Map& map) const;
  // Median depth of its map points in this keyframe's camera (q = 2 median).
  double SceneMedianDepth(const class Map& map) const;
  std::string TraceId() const { return "kf" + std::to_string(id); }
};

class Map {
 public:
  std::map<int64_t, std::unique_ptr<KeyFrame>> keyframes;
  std::map<int64_t, std::unique_ptr<MapPoint>> points;
  std::map<int64_t, std::unique_ptr<MapLine>> lines;    // structure landmarks (map/structure.h)
  std::map<int64_t, std::unique_ptr<MapPlane>> planes;

  KeyFrame* AddKeyFrame(std::unique_ptr<KeyFrame> kf);
  MapPoint* NewMapPoint(const Eigen::Vector3d& X_w, int64_t ref_kf, int frame_index);
  // Look-ups by id through arrays indexed by id (ids are 0, 1, 2, ... and keyframes / points are
  // never erased, only marked bad): the tracker looks up tens of thousands per frame, and a tree
  // walk per look-up made tracking cost grow with the map (issue 18).
  KeyFrame* kf(int64_t id) { return ById(kf_by_id_, id); }
  const KeyFrame* kf(int64_t id) const { return ById(kf_by_id_, id); }
  MapPoint* mp(int64_t id) { return ById(mp_by_id_, id); }
  const MapPoint* mp(int64_t id) const { return ById(mp_by_id_, id); }
  // Valid (exists and not bad) map point or nullptr.
  MapPoint* good_mp(int64_t id) { MapPoint* p = mp(id); return p && !p->bad ? p : nullptr; }
  const MapPoint* good_mp(int64_t id) const { const MapPoint* p = mp(id); return p && !p->bad ? p : nullptr; }
  int64_t next_kf_id() const { return next_kf_id_; }
  size_t GoodPointCount() const;
  // T_cw of a keyframe, following the parent chain through culled ones (ORB-SLAM2 trajectory).
  SE3 ResolvedT_cw(int64_t kf_id) const;

  // ---- observation bookkeeping (ORB-SLAM2 AddObservation / EraseObservation / Replace) ----
  void AddObservation(int64_t mp_id, int64_t kf_id, int idx);
  void EraseObservation(int64_t mp_id, int64_t kf_id);  // may set the point bad (< 3 obs RGB-D: 2)
  void SetBadPoint(int64_t mp_id);
  void ReplacePoint(int64_t mp_id, int64_t by_id);
  void SetBadKeyFrame(int64_t kf_id);  // ORB-SLAM2 SetBadFlag without spanning-tree repair detail
  // Recomputes descriptor, normal and distances of a point from its observations.
  void UpdatePointDescriptor(int64_t mp_id);
  void UpdatePointNormalAndDepth(int64_t mp_id);
  // Recomputes covisibility weights of kf (>= 15 shared points, else the best one).
  void UpdateConnections(int64_t kf_id);

  // ---- line and plane landmarks (structure_map.cpp) ----
  MapLine* NewMapLine(const Eigen::Vector3d& P_s, const Eigen::Vector3d& P_e, const cv::Mat& descriptor,
                      int64_t kf_id, int frame_index);
  MapPlane* NewMapPlane(const Eigen::Vector3d& n_w, double d_w, int64_t kf_id, int frame_index);
  MapLine* good_line(int64_t id);
  const MapLine* good_line(int64_t id) const;
  MapPlane* good_plane(int64_t id);
  const MapPlane* good_plane(int64_t id) const;
  void AddLineObservation(int64_t line_id, int64_t kf_id, int idx);
  void AddPlaneObservation(int64_t plane_id, int64_t kf_id, int idx);
  void SetBadLine(int64_t line_id);    // culled: observations dropped, event kCulled
  // Plane merging: every observation of `plane_id` moves to `by_id` (event kReplaced).
  void ReplacePlane(int64_t plane_id, int64_t by_id);
  size_t GoodLineCount() const;
  size_t GoodPlaneCount() const;

  // ---- landmark lifecycle events (landmark.h) ----
  // Observers are called in registration order, synchronously, when a point is created, replaced
  // or set bad; they must not modify the map. Not owned.
  void AddObserver(LandmarkObserver* observer) { observers_.push_back(observer); }
  void RemoveObserver(LandmarkObserver* observer);

 private:
  template <class T>
  static T* ById(const std::vector<T*>& v, int64_t id) {
    return id >= 0 && static_cast<uint64_t>(id) < v.size() ? v[static_cast<size_t>(id)] : nullptr;
  }
  std::vector<KeyFrame*> kf_by_id_;  // keyframes[id].get(), added with them
  std::vector<MapPoint*> mp_by_id_;  // points[id].get()
  void Notify(LandmarkEvent::Kind kind, int64_t mp_id, int64_t by_id = -1);
  void NotifyTyped(LandmarkEvent::Kind kind, LandmarkType type, int64_t id, int64_t by_id = -1);
  void EraseStructureObservations(KeyFrame& k);  // keyframe culling
  std::vector<LandmarkObserver*> observers_;
  int64_t next_kf_id_ = 0;
  int64_t next_mp_id_ = 0;
  int64_t next_line_id_ = 0, next_plane_id_ = 0;
};

}  // namespace dynref
