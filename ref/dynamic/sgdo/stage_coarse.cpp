// sgdo.coarse (kBeforeInitialPose). seed 001, Sec. 3.3, Eq. (5): coarse rejection.
//   a. LK pairs: each current keypoint tracked back into frame k-1 (spec 001 E2);
//   b. pairs pruned for F: LK failure, border b_edge, 3x3 SAD > c_patch, P2 in M;
//   c. F by RANSAC 7-point with Rng(seed, "sgdo.F") (one stream per run, drawn in frame order);
//   d. D per tracked keypoint whose pair was not pruned for its flow (border, patch SAD: issue 21;
//      a pair pruned only for lying in M is still tested, that is the point of the test),
//      geometric-dynamic iff D > th_epi; without a valid F nothing is tested ("no-F");
//   e. combination with M per `combination` (spec 001 E1, see coarse.h).
// Coordinates: raw keypoint positions for LK; undistorted (cv::undistortPoints, K kept) for F
// and D when the camera has distortion (TUM fr3 and synthetic: none).

#include "dynamic/sgdo/stages.h"

namespace dynref::sgdo {
namespace {

// Trace code of LkPair::prune_reason: 0 usable, 1 lk-failed, 2 border, 3 patch-sad, 4 in-mask;
// 5 = no previous frame image (nothing tracked, README "Trace").
constexpr int kPruneNoPrevious = 5;
int PruneCode(const std::string& reason) {
  if (reason.empty()) return 0;
  if (reason == "lk-failed") return 1;
  if (reason == "border") return 2;
  if (reason == "patch-sad") return 3;
  return 4;
}

// Non-excluded keypoints (ascending index); their mask instance when the combination uses masks.
std::vector<int> CoarseStepCandidates(const Frame& f, const DynamicMask* mask, std::vector<CoarseInput>* inputs) {
  std::vector<int> candidates;
  for (int i = 0; i < static_cast<int>(f.N()); ++i) {
    if (f.IsExcluded(i)) continue;
    candidates.push_back(i);
    if (mask) (*inputs)[i].instance = mask->InstanceAt(f.keys[i].pt.x, f.keys[i].pt.y);
  }
  return candidates;
}

// b. Every candidate tracked back into k-1 (LK), pruned; F and D on undistorted coordinates.
std::vector<geometry::LkPair> CoarseStepTrackPairs(const Camera& cam, const Frame& prev, const Frame& f,
                                                   const std::vector<int>& candidates,
                                                   const std::vector<CoarseInput>& inputs,
                                                   const geometry::LkOptions& lk) {
  std::vector<cv::Point2f> pts;
  for (int i : candidates) pts.push_back(f.keys[i].pt);
  std::vector<geometry::LkPair> pairs = geometry::TrackBackward(prev.grey, f.grey, pts, lk);
  for (size_t c = 0; c < candidates.size(); ++c)
    geometry::PrunePair(prev.grey, f.grey, inputs[candidates[c]].instance != 0, lk, pairs[c]);
  if (cam.HasDistortion()) {  // F and D on undistorted coordinates
    std::vector<cv::Point2f> ua, ub;
    geometry::UndistortedPairPixels(cam, pairs, &ua, &ub);
    for (size_t c = 0; c < pairs.size(); ++c) pairs[c].p_prev = ua[c], pairs[c].p_cur = ub[c];
  }
  return pairs;
}

// c. RANSAC on the usable pairs; f_inlier per pair.
geometry::RansacResult CoarseStepFitF(const std::vector<geometry::LkPair>& pairs, const geometry::RansacOptions& ransac,
                                      Rng& rng, std::vector<geometry::Correspondence>* usable,
                                      std::vector<uint8_t>* f_inlier) {
  std::vector<size_t> usable_of;  // index into pairs
  for (size_t c = 0; c < pairs.size(); ++c)
    if (pairs[c].usable_for_F()) {
      usable->push_back({{pairs[c].p_prev.x, pairs[c].p_prev.y}, {pairs[c].p_cur.x, pairs[c].p_cur.y}});
      usable_of.push_back(c);
    }
  const geometry::RansacResult F = geometry::RansacFundamental(*usable, ransac, rng);
  f_inlier->assign(pairs.size(), 0);
  for (size_t u = 0; u < usable_of.size() && F.valid; ++u) (*f_inlier)[usable_of[u]] = F.inliers[u];
  return F;
}

void CoarseStepTraceF(trace::TraceWriter& tr, const Frame& f, const geometry::RansacResult& F, size_t usable) {
  tr.ProbabilityUpdate("sgdo.F", trace::EntityKind::kFrame, "f" + std::to_string(f.index),
                       {{"F00", F.F(0, 0)}, {"F01", F.F(0, 1)}, {"F02", F.F(0, 2)}, {"F10", F.F(1, 0)},
                        {"F11", F.F(1, 1)}, {"F12", F.F(1, 2)}, {"F20", F.F(2, 0)}, {"F21", F.F(2, 1)},
                        {"F22", F.F(2, 2)}, {"usable", static_cast<double>(usable)},
                        {"inliers", static_cast<double>(F.inlier_count)}},
                       0.0, F.valid ? 1.0 : 0.0);
}

// A candidate record when there are no pairs (no previous frame image, issue 32).
void CoarseStepTraceNoPairs(trace::TraceWriter& tr, const Frame& f, const std::vector<int>& candidates,
                            const std::vector<CoarseInput>& inputs, double th_epi_px) {
  for (int i : candidates)
    tr.ProbabilityUpdate("sgdo.epipolar", trace::EntityKind::kFeature, f.FeatureId(i),
                         {{"u_prev", 0.0}, {"v_prev", 0.0}, {"u_cur", f.keys[i].pt.x}, {"v_cur", f.keys[i].pt.y},
                          {"D_px", 0.0}, {"th_epi_px", th_epi_px},
                          {"instance", static_cast<double>(inputs[i].instance)}, {"used_for_F", 0.0},
                          {"F_inlier", 0.0}, {"patch_sad", 0.0}, {"tracked", 0.0}, {"F_valid", 0.0},
                          {"prune", static_cast<double>(kPruneNoPrevious)}, {"tested", 0.0}},
                         0.0, 0.5);
}

// d. Epipolar distance per tracked keypoint (or why there is none); returns the number tracked.
int64_t CoarseStepDistances(trace::TraceWriter& tr, bool full, const Frame& f, const std::vector<geometry::LkPair>& pairs,
                            const std::vector<int>& candidates, const geometry::RansacResult& F,
                            const std::vector<uint8_t>& f_inlier, double th_epi_px, std::vector<CoarseInput>* inputs) {
  int64_t tracked = 0;
  for (size_t c = 0; c < pairs.size(); ++c) {
    const geometry::LkPair& pr = pairs[c];
    const int i = candidates[c];
    CoarseInput& in = (*inputs)[i];
    const bool flow_pruned = pr.prune_reason == "border" || pr.prune_reason == "patch-sad";
    if (pr.tracked) ++tracked;
    if (!pr.tracked) in.no_distance = "no-pair";
    else if (flow_pruned) in.no_distance = "pruned";
    else if (!F.valid) in.no_distance = "no-F";
    const bool test = pr.tracked && !flow_pruned && F.valid;
    if (test) {
      in.has_distance = true;
      in.epipolar_distance_px = geometry::EpipolarDistance(F.F, {pr.p_prev.x, pr.p_prev.y}, {pr.p_cur.x, pr.p_cur.y});
    }
    const bool dyn = test && in.epipolar_distance_px > th_epi_px;
    // p(dynamic): 1 geometric-dynamic, 0 static, 0.5 not tested (no pair, pruned flow, no F).
    if (full)
      tr.ProbabilityUpdate("sgdo.epipolar", trace::EntityKind::kFeature, f.FeatureId(i),
                           {{"u_prev", pr.p_prev.x}, {"v_prev", pr.p_prev.y}, {"u_cur", pr.p_cur.x},
                            {"v_cur", pr.p_cur.y}, {"D_px", in.epipolar_distance_px},
                            {"th_epi_px", th_epi_px},
                            {"instance", static_cast<double>(in.instance)},
                            {"used_for_F", pr.usable_for_F() ? 1.0 : 0.0},
                            {"F_inlier", f_inlier[c] ? 1.0 : 0.0}, {"patch_sad", pr.patch_sad},
                            {"tracked", pr.tracked ? 1.0 : 0.0}, {"F_valid", F.valid ? 1.0 : 0.0},
                            {"prune", static_cast<double>(PruneCode(pr.prune_reason))}, {"tested", test ? 1.0 : 0.0}},
                           0.0, test ? (dyn ? 1.0 : 0.0) : 0.5);
  }
  return tracked;
}

// e. Combination and decisions (candidates only; already excluded keys are left alone); returns
// the number of decisions per reason.
std::map<std::string, int64_t> CoarseStepDecide(StageContext& ctx, const std::string& stage, const Frame& f,
                                                const std::vector<int>& candidates,
                                                const std::vector<CoarseInput>& inputs, const CoarseOptions& coarse,
                                                bool full) {
  trace::TraceWriter& tr = ctx.trace;
  std::vector<CoarseInput> cand_inputs;
  for (int i : candidates) cand_inputs.push_back(inputs[i]);
  const CoarseResult res = CombineCoarse(cand_inputs, coarse);
  for (const auto& v : res.votes) {
    if (!full) break;
    const std::string id = "i" + std::to_string(f.index) + "." + std::to_string(v.instance);
    tr.ProbabilityUpdate("sgdo.vote", trace::EntityKind::kInstanceMask, id,
                         {{"dynamic", static_cast<double>(v.dynamic)},
                          {"paired", static_cast<double>(v.paired)}, {"vote_ratio", coarse.vote_ratio}},
                         0.0, v.moving ? 1.0 : 0.0);  // p(dynamic) of the instance
  }
  std::map<std::string, int64_t> by_reason;
  for (size_t c = 0; c < candidates.size(); ++c) {
    const CoarseDecision& d = res.decisions[c];
    ++by_reason[d.reason];
    if (d.keep)
      tr.Decision(stage, trace::EntityKind::kFeature, f.FeatureId(candidates[c]), true, d.reason);
    else
      ctx.frame.Exclude(candidates[c], stage, d.reason);
  }
  return by_reason;
}

}  // namespace

CoarseStage::CoarseStage(const ParamMap& p, std::shared_ptr<Blackboard> board)
    : board_(std::move(board)), rng_(static_cast<uint64_t>(p.GetInt("ransac_seed")), "sgdo.F") {
  p.RequireKnownKeys({"combination", "th_epi_px", "vote_ratio", "lk_window_px", "lk_max_level",
                       "lk_max_iterations", "lk_epsilon", "border_px", "patch_sad_max",
                       "ransac_threshold_px", "ransac_confidence", "ransac_max_iterations",
                       "ransac_seed"});
  coarse_.mode = [&] {
    try {
      return ParseCoarseMode(p.GetString("combination"));
    } catch (const std::invalid_argument& e) {
      throw InputError(p.Get("combination").file, p.Get("combination").line, e.what());
    }
  }();
  if (coarse_.mode == CoarseMode::kMaskOnly)
    throw InputError(p.file, p.line, "sgdo.coarse: mask_only is the (S) variant: use sgdo.mask reject_in_mask");
  coarse_.epipolar_threshold_px = p.GetDouble("th_epi_px");
  coarse_.vote_ratio = p.GetDouble("vote_ratio");
  lk_.window_px = static_cast<int>(p.GetInt("lk_window_px"));
  lk_.max_level = static_cast<int>(p.GetInt("lk_max_level"));
  lk_.max_iterations = static_cast<int>(p.GetInt("lk_max_iterations"));
  lk_.epsilon = p.GetDouble("lk_epsilon");
  lk_.border_px = static_cast<int>(p.GetInt("border_px"));
  lk_.patch_sad_max = p.GetDouble("patch_sad_max");
  ransac_.inlier_threshold_px = p.GetDouble("ransac_threshold_px");
  ransac_.confidence = p.GetDouble("ransac_confidence");
  ransac_.max_iterations = static_cast<int>(p.GetInt("ransac_max_iterations"));
  try {
    coarse_.Check();
    lk_.Check();
    ransac_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage sgdo.coarse: " + std::string(e.what()));
  }
}

void CoarseStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  const int n = static_cast<int>(f.N());
  const bool uses_mask = coarse_.mode != CoarseMode::kEpipolarOnly;
  if (uses_mask && !board_->Has(f))
    throw std::logic_error("sgdo.coarse with combination " + std::string(CoarseModeName(coarse_.mode)) +
                           " needs sgdo.mask earlier in the stage list");
  const DynamicMask* mask = uses_mask ? &board_->mask : nullptr;
  trace::TraceWriter& tr = ctx.trace;

  std::vector<CoarseInput> inputs(n);
  const std::vector<int> candidates = CoarseStepCandidates(f, mask, &inputs);  // non-excluded, ascending

  std::vector<geometry::LkPair> pairs;
  const Frame* prev = ctx.previous;
  if (prev != nullptr && !prev->grey.empty() && !candidates.empty()) {
    lk_.threads = ctx.threads;
    pairs = CoarseStepTrackPairs(ctx.camera, *prev, f, candidates, inputs, lk_);
  }

  // c. RANSAC on the usable pairs.
  std::vector<geometry::Correspondence> usable;
  std::vector<uint8_t> f_inlier;
  const geometry::RansacResult F = CoarseStepFitF(pairs, ransac_, rng_, &usable, &f_inlier);

  // d. Epipolar distance per tracked keypoint, traced for every candidate (also when there is
  // none: why). F itself is traced per frame.
  // (Also on a frame without a previous image: every candidate then has a record too, issue 32.)
  const bool full = tr.full_enabled();
  if (full && !candidates.empty()) CoarseStepTraceF(tr, f, F, usable.size());
  if (full && pairs.empty()) CoarseStepTraceNoPairs(tr, f, candidates, inputs, coarse_.epipolar_threshold_px);
  const int64_t tracked =
      CoarseStepDistances(tr, full, f, pairs, candidates, F, f_inlier, coarse_.epipolar_threshold_px, &inputs);
  // e. Combination and decisions (candidates only; already excluded keys are left alone).
  const std::map<std::string, int64_t> by_reason = CoarseStepDecide(ctx, name(), f, candidates, inputs, coarse_, full);
  int64_t usable_count = static_cast<int64_t>(usable.size());
  tr.FrameCount(name(), "tracked", tracked);
  tr.FrameCount(name(), "usable_for_F", usable_count);
  tr.FrameCount(name(), "F_valid", F.valid ? 1 : 0);
  tr.FrameCount(name(), "F_inliers", F.inlier_count);
  tr.FrameCount(name(), "ransac_iterations", F.iterations);
  for (const auto& [reason, count] : by_reason) tr.FrameCount(name(), "decision:" + reason, count);
}

}  // namespace dynref::sgdo
