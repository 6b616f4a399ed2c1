#include "method/frame_edit.h"

#include <stdexcept>

namespace dynref {

void FrameEdit::RequireFeatures(const char* what) const {
  if (hook_ == Hook::kBeforeExtraction)
    throw std::logic_error(std::string(what) + " before feature extraction (hook before_extraction)");
}

void FrameEdit::Exclude(int i, const std::string& stage, const std::string& reason) {
  RequireFeatures("FrameEdit::Exclude");
  frame_.Exclude(i, stage, reason);
}

void FrameEdit::SetWeight(int i, double w) {
  RequireFeatures("FrameEdit::SetWeight");
  frame_.SetWeight(i, w);
}

namespace {

// A landmark's dynamic state (map point or map line); `what` names the caller in errors.
void SetDynamicState(LandmarkDynamicState* d, const char* what, const std::string& landmark, double p, int frame,
                     const std::string& stage) {
  if (d == nullptr) throw std::logic_error(std::string(what) + ": no " + landmark);
  if (!(p >= 0.0 && p <= 1.0)) throw std::logic_error(std::string(what) + ": p outside [0, 1]");
  d->p_dynamic = p;
  d->frame = frame;
  d->stage = stage;
}

}  // namespace

void FrameEdit::SetPointDynamicProbability(int64_t mp_id, double p, const std::string& stage) {
  MapPoint* mp = map_.mp(mp_id);
  SetDynamicState(mp ? &mp->dynamic : nullptr, "SetPointDynamicProbability", "map point " + std::to_string(mp_id), p,
                  frame_.index, stage);
}

void FrameEdit::SetLineWeight(int i, double w) {
  RequireFeatures("FrameEdit::SetLineWeight");
  std::vector<double>& lw = frame_.structure.line_weight;
  if (i < 0 || static_cast<size_t>(i) >= lw.size())
    throw std::logic_error("SetLineWeight: no line " + std::to_string(i) + " in frame " + std::to_string(frame_.index));
  if (!(w >= 0.0 && w <= 1.0)) throw std::logic_error("SetLineWeight: w outside [0, 1]");
  lw[static_cast<size_t>(i)] = w;
}

void FrameEdit::SetLineDynamicProbability(int64_t ml_id, double p, const std::string& stage) {
  MapLine* l = map_.good_line(ml_id);
  SetDynamicState(l ? &l->dynamic : nullptr, "SetLineDynamicProbability", "map line " + std::to_string(ml_id), p,
                  frame_.index, stage);
}

cv::Mat& FrameEdit::grey_for_extraction() {
  if (hook_ != Hook::kBeforeExtraction)
    throw std::logic_error("FrameEdit::grey_for_extraction outside the before_extraction hook");
  return frame_.grey;
}

}  // namespace dynref
