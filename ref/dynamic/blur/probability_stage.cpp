// blur.probability: seed 003 Sec. 3.3 (spec 003 step 5) on the keypoints of the current frame and
// M_sd from blur.mask. Every keypoint's pre-defined P, neighbour counts and final P are traced;
// dynamic ones are excluded (Frame::Exclude logs the decision) before any matching.
#include <stdexcept>

#include "core/error.h"
#include "dynamic/blur/components.h"

namespace dynref::blur {

ProbabilityStage::ProbabilityStage(const ParamMap& p, std::shared_ptr<Board> board) : board_(std::move(board)) {
  p.RequireKnownKeys({"compute", "radius_px", "c1", "c2", "theta"});
  o_.compute = p.GetBool("compute");
  o_.radius_px = p.GetDouble("radius_px");
  o_.c1 = p.GetDouble("c1");
  o_.c2 = p.GetDouble("c2");
  o_.theta = p.GetDouble("theta");
  try {
    o_.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage blur.probability: " + std::string(e.what()));
  }
}

void ProbabilityStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  if (!board_->Has(f)) throw std::logic_error("blur.probability needs blur.mask earlier in the same frame (config order)");
  const cv::Mat& m = board_->mask;
  std::vector<cv::Point2f> pts;
  std::vector<uint8_t> in_mask;
  std::vector<int> index;  // keypoints not excluded by an earlier stage
  for (size_t i = 0; i < f.N(); ++i) {
    if (f.IsExcluded(int(i))) continue;
    const cv::Point2f p = f.keys[i].pt;
    const int x = int(p.x + 0.5f), y = int(p.y + 0.5f);
    pts.push_back(p);
    in_mask.push_back(x >= 0 && y >= 0 && x < m.cols && y < m.rows && m.at<uint8_t>(y, x) ? 1 : 0);
    index.push_back(int(i));
  }
  const std::vector<KeypointProbability> kp = KeypointProbabilities(pts, in_mask, o_);
  trace::TraceWriter& tr = ctx.trace;
  int64_t in_m = 0, by_probability = 0;
  for (size_t k = 0; k < kp.size(); ++k) {
    const KeypointProbability& p = kp[k];
    // x, y: the keypoint coordinates the neighbour search and the mask look-up used (Frame::keys,
    // before undistortion; OBS u, v are the undistorted ones, equal on undistorted cameras).
    if (tr.full_enabled())
      tr.ProbabilityUpdate(name(), trace::EntityKind::kFeature, f.FeatureId(index[k]),
                           {{"x", double(pts[k].x)}, {"y", double(pts[k].y)}, {"neighbours", double(p.neighbours)},
                            {"dynamic_neighbours", double(p.dynamic_neighbours)}, {"radius_px", o_.radius_px},
                            {"theta", o_.theta}},
                           p.pre, p.post);
    if (!p.dynamic) continue;
    const bool mask = p.pre > 0;
    in_m += mask, by_probability += !mask;
    ctx.frame.Exclude(index[k], name(), mask ? "in-mask" : "probability>theta");
  }
  tr.FrameCount(name(), "keypoints", int64_t(kp.size()));
  tr.FrameCount(name(), "removed_in_mask", in_m);
  tr.FrameCount(name(), "removed_by_probability", by_probability);
}

}  // namespace dynref::blur
