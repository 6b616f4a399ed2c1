// ORB-SLAM2 ORBmatcher::SearchByBoW(KeyFrame*, Frame&, vector<MapPoint*>&) (issue 34): keyframe-to-
// frame matching restricted to features under the same vocabulary node (the FeatureVectors of
// tracking/place_index.h), with ORB-SLAM2's rules: for each keyframe feature with a good map
// point, the nearest and second-nearest frame feature of the same node that is still unmatched
// and not excluded; accepted when best <= TH_LOW and best < nn_ratio * second (first come, one to
// one), then the rotation histogram keeps the three fullest bins. Nodes are visited in ascending
// id, features in ascending index (ORB-SLAM2's iteration order of its ordered maps).
#pragma once
#include "map/frame.h"
#include "map/map.h"
#include "tracking/place_index.h"

namespace dynref::tracking {

// Writes the matched map point ids into cur.map_point_ids; returns the number of matches.
int SearchByBoW(const KeyFrame& kf, const PlaceBow& kf_bow, Frame& cur, const PlaceBow& cur_bow, const Map& map,
                float nn_ratio, bool check_orientation);

}  // namespace dynref::tracking
