// ORB-SLAM2 LoopClosing, sequential; see loop_closer.h (steps) and README.md (trace records).
#include "loop/loop_closer.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "core/cpu_clock.h"
#include "core/error.h"
#include "loop/essential_graph.h"
#include "loop/loop_matcher.h"

namespace dynref::loop {
namespace {

std::string Kf(int64_t id) { return "kf" + std::to_string(id); }

}  // namespace

void LoopClosingOptions::Check() const {
  detector.Check();
  if (bow_min_matches < 3) throw InputError("loop options", "bow_min_matches must be >= 3");
  if (ransac.min_inliers < 3) throw InputError("loop options", "ransac min_inliers must be >= 3");
  if (ransac.max_iterations < 1) throw InputError("loop options", "ransac max_iterations must be >= 1");
  if (min_loop_matches < 0) throw InputError("loop options", "min_loop_matches must be >= 0");
  if (essential_iterations < 0 || global_ba_iterations < 0) throw InputError("loop options", "iterations must be >= 0");
}

LoopCloser::LoopCloser(Map& map, const Camera& camera, const LoopClosingOptions& options,
                       const optim::LocalBAOptions& ba, trace::TraceWriter& trace)
    : map_(map), camera_(camera), options_(options), ba_(ba), trace_(trace), detector_(options.detector),
      rng_(options.seed, "loop.se3") {
  options_.Check();
  ba_.iterations_robust = options_.global_ba_iterations;  // Huber throughout (ORB-SLAM2: none, loop_closer.h)
  ba_.iterations_refine = 0;
}

bool LoopCloser::Process(int64_t kf_id, tracking::PlaceIndex& place) {
  KeyFrame* kf = map_.kf(kf_id);
  if (kf == nullptr || kf->bad) return false;
  const double t0 = ThreadCpuMs();
  Candidate c;
  const bool found = DetectAndMatch(*kf, place, &c);
  const double t1 = ThreadCpuMs();
  ++timing_.keyframes;
  timing_.detect_ms += t1 - t0;
  if (!found) return false;
  const double ba_before = timing_.global_ba_ms;
  LoopEvent event;
  event.kf = kf_id;
  event.loop_kf = c.loop_kf;
  event.bow_matches = c.bow_matches;
  event.se3_inliers = c.se3_inliers;
  event.loop_matches = c.loop_matches;
  event.T_cw_before = kf->T_cw;
  CorrectLoop(*kf, c, &event);
  event.T_cw_after = kf->T_cw;
  const Eigen::Quaterniond q(event.T_cw_after.linear());
  const Eigen::Vector3d t = event.T_cw_after.translation();
  const Eigen::Vector3d moved = event.T_cw_after.inverse().translation() - event.T_cw_before.inverse().translation();
  trace_.ProbabilityUpdate("loop.transform", trace::EntityKind::kKeyFrame, Kf(kf_id),
                           {{"loop_kf", static_cast<double>(c.loop_kf)},
                            {"tx", t.x()}, {"ty", t.y()}, {"tz", t.z()},
                            {"qx", q.x()}, {"qy", q.y()}, {"qz", q.z()}, {"qw", q.w()},
                            {"moved_m", moved.norm()}},
                           0.0, 0.0);
  trace_.FrameCount("loop", "closed", 1);
  loops_.push_back(event);
  detector_.SetLastLoop(kf_id);
  ++timing_.loops;
  timing_.correct_ms += ThreadCpuMs() - t1 - (timing_.global_ba_ms - ba_before);
  return true;
}

bool LoopCloser::DetectAndMatch(KeyFrame& kf, tracking::PlaceIndex& place, Candidate* out) {
  const int64_t kf_id = kf.id;
  place.EraseBad(map_);
  const LoopDetection d = detector_.Detect(kf, map_, place);
  if (d.skipped) return false;
  trace_.FrameCount("loop", "candidates", static_cast<int64_t>(d.candidates.size()));
  for (const LoopCandidate& c : d.candidates) {
    trace_.ProbabilityUpdate("loop.candidate", trace::EntityKind::kKeyFrame, Kf(c.kf),
                             {{"query", static_cast<double>(kf_id)},
                              {"score", c.score},
                              {"min_score", d.min_score},
                              {"consistency", static_cast<double>(c.consistency)},
                              {"threshold", static_cast<double>(options_.detector.consistency)}},
                             0.0, c.accepted ? 1.0 : 0.0);
    trace_.Decision("loop.candidate", trace::EntityKind::kKeyFrame, Kf(c.kf), c.accepted, c.reason);
  }
  if (d.accepted.empty()) return false;
  return ComputeSe3(kf, d.accepted, place, out);
}

bool LoopCloser::ComputeSe3(const KeyFrame& kf, const std::vector<int64_t>& accepted,
                            const tracking::PlaceIndex& place, Candidate* out) {
  const tracking::PlaceBow* own = place.Of(kf.id);
  const Intrinsics K = camera_.Pinhole();
  for (int64_t cand_id : accepted) {
    const KeyFrame* cand = map_.kf(cand_id);
    const tracking::PlaceBow* cb = place.Of(cand_id);
    Candidate c;
    c.loop_kf = cand_id;
    std::string reason = "loop";
    if (cand == nullptr || cand->bad || cb == nullptr || own == nullptr) {
      reason = "bad-keyframe";
    } else {
      const std::vector<int64_t> bow = SearchByBoWKeyFrames(kf, *own, *cand, *cb, map_, 0.75f);
      std::vector<Se3Match> matches;
      std::vector<int> feature;  // keyframe feature of each match
      for (size_t i = 0; i < bow.size(); ++i) {
        if (bow[i] < 0) continue;
        const MapPoint* p1 = map_.good_mp(kf.map_point_ids[i]);
        const MapPoint* p2 = map_.good_mp(bow[i]);
        const auto obs2 = p2 != nullptr ? p2->observations.find(cand_id) : std::map<int64_t, int>::const_iterator{};
        if (p1 == nullptr || p2 == nullptr || obs2 == p2->observations.end()) continue;
        const cv::KeyPoint& k1 = kf.frame.keys_un[i];
        const cv::KeyPoint& k2 = cand->frame.keys_un[obs2->second];
        Se3Match m;
        m.X1 = kf.T_cw * p1->X_w;
        m.X2 = cand->T_cw * p2->X_w;
        m.uv1 = {k1.pt.x, k1.pt.y};
        m.uv2 = {k2.pt.x, k2.pt.y};
        m.sigma2_1 = kf.frame.pyramid.sigma2[k1.octave];
        m.sigma2_2 = cand->frame.pyramid.sigma2[k2.octave];
        matches.push_back(m);
        feature.push_back(static_cast<int>(i));
      }
      c.bow_matches = static_cast<int>(matches.size());
      if (c.bow_matches < options_.bow_min_matches) {
        reason = "few-bow-matches";
      } else {
        const Se3RansacResult r = Se3Ransac(matches, K, options_.ransac, rng_);
        c.se3_inliers = r.num_inliers;
        if (!r.ok) {
          reason = "ransac-failed";
        } else {
          c.T_cw = r.T_12 * cand->T_cw;
          c.matched.assign(kf.N(), -1);
          for (size_t m = 0; m < matches.size(); ++m)
            if (r.inlier[m]) c.matched[feature[m]] = bow[feature[m]];
          // The loop keyframe's and its covisibles' points (ORB-SLAM2 mvpLoopMapPoints).
          std::vector<int64_t> group{cand_id};
          for (int64_t g : cand->ordered_covisibles) group.push_back(g);
          std::set<int64_t> seen;
          for (int64_t g : group) {
            const KeyFrame* gk = map_.kf(g);
            if (gk == nullptr || gk->bad) continue;
            for (int64_t id : gk->map_point_ids)
              if (id >= 0 && map_.good_mp(id) != nullptr && seen.insert(id).second) c.loop_points.push_back(id);
          }
          SearchByProjectionPose(kf, c.T_cw, c.loop_points, map_, 10.0f, &c.matched);
          for (int64_t id : c.matched) c.loop_matches += id >= 0;
          if (c.loop_matches < options_.min_loop_matches) reason = "few-loop-matches";
        }
      }
    }
    const bool ok = reason == "loop";
    trace_.ProbabilityUpdate("loop.geometry", trace::EntityKind::kKeyFrame, Kf(cand_id),
                             {{"query", static_cast<double>(kf.id)},
                              {"bow_matches", static_cast<double>(c.bow_matches)},
                              {"bow_min", static_cast<double>(options_.bow_min_matches)},
                              {"se3_inliers", static_cast<double>(c.se3_inliers)},
                              {"se3_min", static_cast<double>(options_.ransac.min_inliers)},
                              {"loop_matches", static_cast<double>(c.loop_matches)},
                              {"loop_min", static_cast<double>(options_.min_loop_matches)}},
                             0.0, ok ? 1.0 : 0.0);
    trace_.Decision("loop.geometry", trace::EntityKind::kKeyFrame, Kf(cand_id), ok, reason);
    if (ok) {
      *out = std::move(c);
      return true;
    }
  }
  return false;
}

}  // namespace dynref::loop
