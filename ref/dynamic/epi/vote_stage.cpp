// epi.vote: seed 004 Module C (Sec. 3.3.1, spec 004 steps 5a-5e).
//   a. S0 = image minus the prior-dynamic instance masks (Eq. (8)-(9)); A_s = keypoints in S0.
//   b. Matches k-1 <-> k: every keypoint tracked back into k-1 by Lucas-Kanade (geometry/lk_pairs,
//      as sgdo), pruned at the border and by patch SAD; relative pose (R, t) from the A_s pairs with
//      depth in both frames (RGB-D rigid RANSAC, geometry/rigid_ransac: "estimated assuming all
//      points static"); Eq. (12) F = K^-T [t]x R K^-1 (geometry::FundamentalFromPose).
//   c. Eq. (14): D = |A u + B v + C| / sqrt(A^2 + B^2) of every tracked in-mask keypoint, l = F p_(k-1)
//      (mask_vote.h VoteGeometry; t = 0: the rotation-only limit |p_k - K R K^-1 p_(k-1)|).
//   d. Each mask is dynamic when > 60 % of its matched keypoints have D > eps (mask_vote.h).
//   e. Keypoints of dynamic masks are excluded (matched or not); the rest are the static set.
// Without a previous frame or a pose (too few static pairs) every mask is dynamic (E8).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/error.h"
#include "dynamic/epi/stages.h"

namespace dynref::epi {

VoteStage::VoteStage(const ParamMap& p, std::shared_ptr<Blackboard> board)
    : rng_(uint64_t(p.GetInt("ransac_seed")), "epi.pose"), board_(std::move(board)), tally_(name(), p) {
  p.RequireKnownKeys({"dynamic_classes", "min_confidence", "threshold_scale", "epi_threshold_px", "vote_ratio", "lk_window_px",
                      "lk_max_level", "border_px", "patch_sad_max", "pose_inlier_px", "pose_iterations",
                      "pose_min_inliers", "ransac_seed"});
  mask_.dynamic_class_ids = p.GetCocoClassIds("dynamic_classes");
  mask_.min_confidence = p.GetDouble("min_confidence");
  mask_.dilation_kernel_px = 1;  // the paper uses the YOLO masks as they are
  vote_.epi_threshold_px = p.GetDouble("epi_threshold_px");
  vote_.vote_ratio = p.GetDouble("vote_ratio");
  lk_.window_px = int(p.GetInt("lk_window_px"));
  lk_.max_level = int(p.GetInt("lk_max_level"));
  lk_.border_px = int(p.GetInt("border_px"));
  lk_.patch_sad_max = p.GetDouble("patch_sad_max");
  pose_.inlier_px = p.GetDouble("pose_inlier_px");
  pose_.iterations = int(p.GetInt("pose_iterations"));
  pose_.min_inliers = int(p.GetInt("pose_min_inliers"));
  try {
    mask_.Check();
    vote_.Check();
    lk_.Check();
    pose_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage epi.vote: " + std::string(e.what()));
  }
}

namespace {

// Non-excluded keypoints and the instance mask each lies in (0: none).
void EpiVoteCandidates(const Frame& f, const geometry::DynamicMask& m, std::vector<int>* candidates,
                       std::vector<int>* instance_of) {
  for (int i = 0; i < int(f.N()); ++i)
    if (!f.IsExcluded(i)) candidates->push_back(i);
  instance_of->assign(candidates->size(), 0);
  for (size_t c = 0; c < candidates->size(); ++c) {
    const cv::Point2f& p = f.keys[size_t((*candidates)[c])].pt;
    (*instance_of)[c] = m.InstanceAt(p.x, p.y);
  }
}

// What the pose step found, and what epi.epipolar records per in-mask keypoint (README "Trace"):
// the pair (undistorted px).
struct EpiVotePose {
  bool have_pose = false;
  int static_pairs = 0, pose_inliers = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  std::vector<cv::Point2f> rec_prev, rec_cur;
  std::vector<uint8_t> rec_tracked;
};

// b. static pairs with depth in both frames (for (R, t)).
std::vector<geometry::PointPair3D> EpiVoteStaticPairs(const Camera& cam, const Frame& f, const Frame& prev,
                                                      const std::vector<int>& candidates,
                                                      const std::vector<int>& instance_of,
                                                      const std::vector<geometry::LkPair>& pairs,
                                                      const std::vector<cv::Point2f>& prev_un,
                                                      const std::vector<cv::Point2f>& cur_un) {
  auto back = [&](const cv::Point2f& u, double z) {
    return Eigen::Vector3d((u.x - cam.cx) / cam.fx * z, (u.y - cam.cy) / cam.fy * z, z);
  };
  std::vector<geometry::PointPair3D> pp;
  for (size_t c = 0; c < pairs.size(); ++c) {
    if (instance_of[c] != 0 || !pairs[c].usable_for_F()) continue;
    const int x = int(std::lround(pairs[c].p_prev.x)), y = int(std::lround(pairs[c].p_prev.y));
    if (x < 0 || y < 0 || x >= prev.depth_m.cols || y >= prev.depth_m.rows) continue;
    const double z_prev = prev.depth_m.at<float>(y, x), z_cur = f.depth[size_t(candidates[c])];
    if (!(z_prev > 0) || !(z_cur > 0)) continue;
    pp.push_back({back(prev_un[c], z_prev), back(cur_un[c], z_cur), {cur_un[c].x, cur_un[c].y}});
  }
  return pp;
}

// b-c. LK pairs k-1 <-> k, the static-region pose, and Eq. (14) D of every tracked in-mask keypoint.
EpiVotePose EpiVoteEstimatePose(const Camera& cam, const Frame& f, const Frame& prev, const std::vector<int>& candidates,
                                const std::vector<int>& instance_of, const geometry::LkOptions& lk,
                                const geometry::RigidRansacOptions& pose_options, Rng& rng, bool full,
                                std::vector<double>* distance) {
  EpiVotePose out;
  std::vector<cv::Point2f> pts;
  for (int i : candidates) pts.push_back(f.keys[size_t(i)].pt);
  std::vector<geometry::LkPair> pairs = geometry::TrackBackward(prev.grey, f.grey, pts, lk);
  for (size_t c = 0; c < pairs.size(); ++c) geometry::PrunePair(prev.grey, f.grey, instance_of[c] != 0, lk, pairs[c]);
  std::vector<cv::Point2f> prev_un, cur_un;  // pose and F on undistorted pixels (depth looked up raw)
  geometry::UndistortedPairPixels(cam, pairs, &prev_un, &cur_un);
  const std::vector<geometry::PointPair3D> pp =
      EpiVoteStaticPairs(cam, f, prev, candidates, instance_of, pairs, prev_un, cur_un);
  out.static_pairs = int(pp.size());
  const geometry::RigidRansacResult pose = geometry::RigidRansac(pp, cam.fx, cam.fy, cam.cx, cam.cy, pose_options, rng);
  out.pose_inliers = pose.inlier_count;
  if (full) {
    out.rec_prev = prev_un, out.rec_cur = cur_un;
    for (const geometry::LkPair& pr : pairs) out.rec_tracked.push_back(pr.tracked ? 1 : 0);
  }
  if (pose.valid) {
    out.have_pose = true;
    out.R = pose.R, out.t = pose.t;
    Eigen::Matrix3d K;
    K << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1;
    const VoteGeometry geometry(K, pose.R, pose.t);
    // c. every tracked in-mask keypoint (pruning concerns the pose only, as in sgdo).
    for (size_t c = 0; c < pairs.size(); ++c) {
      if (instance_of[c] == 0 || !pairs[c].tracked) continue;
      (*distance)[c] = geometry.Distance({prev_un[c].x, prev_un[c].y}, {cur_un[c].x, cur_un[c].y});
    }
  }
  return out;
}

// epi.pose (p = 0: a pose is no evidence of motion): the static-region pose (R, t) = T_cur_prev
// F is built from (zero when no pose; t = 0: VoteDistance's rotation-only limit).
void EpiVoteTracePose(trace::TraceWriter& tr, const std::string& fid, const EpiVotePose& ps, int min_inliers) {
  std::vector<trace::NamedValue> in = {{"static_pairs", double(ps.static_pairs)}, {"inliers", double(ps.pose_inliers)},
                                       {"min_inliers", double(min_inliers)}, {"pose", ps.have_pose ? 1.0 : 0.0}};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) in.push_back({"R" + std::to_string(r) + std::to_string(k), ps.R(r, k)});
  for (int r = 0; r < 3; ++r) in.push_back({"t" + std::to_string(r), ps.t(r)});
  tr.ProbabilityUpdate("epi.pose", trace::EntityKind::kFrame, fid, in, 0.0, 0.0);
}

// epi.epipolar: every in-mask keypoint (its instance: the vote and the exclusion are checked
// against it); the pair and the distance when it has one (after = 1 when D > eps).
void EpiVoteTraceEpipolar(trace::TraceWriter& tr, const Frame& f, const std::vector<int>& candidates,
                          const std::vector<int>& instance_of, const EpiVotePose& ps,
                          const std::vector<double>& distance, double eps_px) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t c = 0; c < candidates.size(); ++c) {
    if (instance_of[c] == 0) continue;
    const bool tracked = c < ps.rec_tracked.size() && ps.rec_tracked[c] != 0;
    tr.ProbabilityUpdate("epi.epipolar", trace::EntityKind::kFeature, f.FeatureId(candidates[c]),
                         {{"instance", double(instance_of[c])}, {"tracked", tracked ? 1.0 : 0.0},
                          {"pose", ps.have_pose ? 1.0 : 0.0},
                          {"u_prev", tracked ? double(ps.rec_prev[c].x) : nan},
                          {"v_prev", tracked ? double(ps.rec_prev[c].y) : nan},
                          {"u_cur", tracked ? double(ps.rec_cur[c].x) : nan},
                          {"v_cur", tracked ? double(ps.rec_cur[c].y) : nan},
                          {"distance_px", distance[c]}, {"eps_px", eps_px}},
                         0.0, distance[c] > eps_px ? 1.0 : 0.0);
  }
}

// d. the decision on each mask (and its vote when tracing in full).
void EpiVoteRecordVotes(trace::TraceWriter& tr, const std::string& stage, const Frame& f,
                        const std::map<int, MaskVote>& votes, const MaskVoteOptions& vote, bool full) {
  for (const auto& [id, v] : votes) {
    const std::string iid = "i" + std::to_string(f.index) + "." + std::to_string(id);
    if (full)  // after = the mask's state (1 dynamic); the ratio is an input
      tr.ProbabilityUpdate("epi.vote", trace::EntityKind::kInstanceMask, iid,
                           {{"matched", double(v.matched)}, {"violating", double(v.violating)}, {"ratio", v.ratio},
                            {"vote_ratio", vote.vote_ratio}},
                           0.0, v.dynamic ? 1.0 : 0.0);
    tr.Decision(stage, trace::EntityKind::kInstanceMask, iid, !v.dynamic,
                v.matched == 0 ? "no-matched-keypoint" : (v.dynamic ? "vote>ratio" : "vote<=ratio"));
  }
}

// e. exclusion of the keypoints of dynamic masks; returns how many were removed.
int64_t EpiVoteExclude(StageContext& ctx, const std::vector<int>& candidates, const std::vector<int>& instance_of,
                       const std::map<int, MaskVote>& votes, const std::string& stage) {
  int64_t removed = 0;
  for (size_t c = 0; c < candidates.size(); ++c) {
    if (instance_of[c] == 0 || !votes.at(instance_of[c]).dynamic) continue;
    ctx.frame.Exclude(candidates[c], stage, "dynamic-mask");
    ++removed;
  }
  return removed;
}

}  // namespace

void VoteStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  if (f.detections == nullptr)
    throw InputError("--detections", "epi.vote needs instance masks for frame " + f.stamp_text + " (run with --detections DIR)");
  const Camera& cam = ctx.camera;
  trace::TraceWriter& tr = ctx.trace;
  const std::string fid = "f" + std::to_string(f.index);
  // min_confidence is the paper's threshold for its detector, mapped to this source (issue 39).
  geometry::DynamicMaskOptions frame_mask = mask_;
  frame_mask.min_confidence = tally_.Threshold(*f.detections);
  for (const DetectedInstance& inst : f.detections->instances)
    if (std::find(mask_.dynamic_class_ids.begin(), mask_.dynamic_class_ids.end(), inst.class_id) !=
        mask_.dynamic_class_ids.end())
      tally_.Count(inst.confidence < frame_mask.min_confidence);
  const geometry::DynamicMask m = geometry::BuildDynamicMask(*f.detections, cam.width, cam.height, frame_mask);

  std::vector<int> candidates, instance_of;  // non-excluded keypoints, their instance
  EpiVoteCandidates(f, m, &candidates, &instance_of);
  std::vector<double> distance(candidates.size(), std::numeric_limits<double>::quiet_NaN());
  const Frame* prev = ctx.previous;
  const bool full = tr.full_enabled();
  EpiVotePose pose;
  if (prev != nullptr && !prev->grey.empty() && !prev->depth_m.empty() && !candidates.empty() && !m.instance_ids.empty()) {
    lk_.threads = ctx.threads;
    pose = EpiVoteEstimatePose(cam, f, *prev, candidates, instance_of, lk_, pose_, rng_, full, &distance);
  }
  if (full) {
    EpiVoteTracePose(tr, fid, pose, pose_.min_inliers);
    EpiVoteTraceEpipolar(tr, f, candidates, instance_of, pose, distance, vote_.epi_threshold_px);
  }
  // d. votes (without a pose: no distance, every mask dynamic, E8).
  const std::map<int, MaskVote> votes = VoteMasks(instance_of, distance, m.instance_ids, vote_);
  EpiVoteRecordVotes(tr, name(), f, votes, vote_, full);
  // e. exclusion.
  const int64_t removed = EpiVoteExclude(ctx, candidates, instance_of, votes, name());
  int64_t dynamic_masks = 0;
  for (const auto& [id, v] : votes) dynamic_masks += v.dynamic;
  // For epi.nerf: the labels (a fresh image per frame, shared, not copied) and the dynamic ids.
  board_->frame_index = f.index;
  board_->stamp_text = f.stamp_text;
  board_->instance_labels = m.instance_labels;
  board_->dynamic_ids.clear();
  for (const auto& [id, v] : votes)
    if (v.dynamic) board_->dynamic_ids.insert(id);
  tr.FrameCount(name(), "masks", int64_t(votes.size()));
  tr.FrameCount(name(), "dynamic_masks", dynamic_masks);
  tr.FrameCount(name(), "keypoints_removed", removed);
}

cv::Mat Blackboard::DynamicMask() const {
  if (instance_labels.empty() || dynamic_ids.empty()) return cv::Mat();
  cv::Mat mask = cv::Mat::zeros(instance_labels.size(), CV_8U);
  for (int y = 0; y < instance_labels.rows; ++y) {
    const uint16_t* label = instance_labels.ptr<uint16_t>(y);
    uint8_t* out = mask.ptr<uint8_t>(y);
    for (int x = 0; x < instance_labels.cols; ++x)
      if (label[x] != 0 && dynamic_ids.count(label[x]) != 0) out[x] = 255;
  }
  return mask;
}

}  // namespace dynref::epi
