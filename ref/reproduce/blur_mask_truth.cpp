#include "reproduce/blur_mask_truth.h"

#include "io/mask_format.h"
#include "io/sequence.h"
#include "synth/scene.h"

namespace dynref::reproduce {

MaskTruth& MaskTruth::operator+=(const MaskTruth& o) {
  frames += o.frames, frames_with_missed += o.frames_with_missed, frames_triggered += o.frames_triggered;
  person_px += o.person_px, missed_px += o.missed_px;
  comp_px += o.comp_px, comp_recovered_px += o.comp_recovered_px, comp_false_px += o.comp_false_px;
  depth_px += o.depth_px, depth_recovered_px += o.depth_recovered_px, depth_false_px += o.depth_false_px;
  final_px += o.final_px, final_covered_px += o.final_covered_px;
  return *this;
}

MaskTruth MeasureMaskTruth(const std::string& seq_dir, const std::string& mode, const blur::FusedMaskOptions& options) {
  const Sequence seq = OpenSequence(seq_dir);
  const std::string det_dir = seq_dir + "/detections/" + mode;
  const DetectionsReader det(det_dir), gt(seq_dir + "/gt");
  const cv::Size size(seq.camera.width, seq.camera.height);
  blur::FusedMaskBuilder builder(options, size);
  MaskTruth t;
  for (const FrameEntry& e : seq.frames) {
    const FrameDetections d = det.Read(e.rgb_stamp_text, size);
    const blur::FusedMask m = builder.Build(d, LoadDepthMeters(seq, e), e.rgb_stamp, det_dir);
    const cv::Mat ids = gt.Read(e.rgb_stamp_text, size).instance_ids;
    cv::Mat person = cv::Mat::zeros(size, CV_8U);
    if (!ids.empty()) person = (ids >= synth::kFirstPersonId) & (ids < synth::kFirstMovableId);
    cv::Mat segmenter = cv::Mat::zeros(size, CV_8U);
    for (const blur::PersonMask& p : m.persons) segmenter |= p.mask;
    const cv::Mat missed = person & ~segmenter;
    const cv::Mat comp = m.origin == blur::kCompensation, depth = m.origin == blur::kDepthFusion;
    const int64_t person_px = cv::countNonZero(person), missed_px = cv::countNonZero(missed);
    ++t.frames;
    t.frames_with_missed += person_px > 0 && missed_px >= 0.05 * double(person_px);
    t.frames_triggered += m.comp.triggered;
    t.person_px += person_px;
    t.missed_px += missed_px;
    t.comp_px += cv::countNonZero(comp);
    t.comp_recovered_px += cv::countNonZero(comp & missed);
    t.comp_false_px += cv::countNonZero(comp & ~person);
    t.depth_px += cv::countNonZero(depth);
    t.depth_recovered_px += cv::countNonZero(depth & missed);
    t.depth_false_px += cv::countNonZero(depth & ~person);
    t.final_px += cv::countNonZero(m.mask);
    t.final_covered_px += cv::countNonZero(m.mask & person);
  }
  return t;
}

}  // namespace dynref::reproduce
