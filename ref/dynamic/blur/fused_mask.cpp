#include "dynamic/blur/fused_mask.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/error.h"

namespace dynref::blur {

void FusedMaskOptions::Check() const {
  if (person_class_ids.empty()) throw std::invalid_argument("person_classes must list a class");
  if (!(min_confidence >= 0 && min_confidence <= 1)) throw std::invalid_argument("min_confidence must be in [0, 1]");
  if (dilation_size < 0 || dilation_size > 100) throw std::invalid_argument("dilation_size must be in 0..100");
  comp.Check();
  depth.Check();
}

namespace {
const FusedMaskOptions& Checked(const FusedMaskOptions& o) {
  o.Check();
  return o;
}
}  // namespace

FusedMaskBuilder::FusedMaskBuilder(const FusedMaskOptions& options, cv::Size image_size)
    : o_(Checked(options)), size_(image_size), compensator_(o_.comp, image_size),
      rng_(o_.sampling_seed, "blur.depth_sampling") {}

FusedMask FusedMaskBuilder::Build(const FrameDetections& det, const cv::Mat& depth_m, double stamp,
                                  const std::string& source, double min_confidence) {
  const double threshold = min_confidence < 0 ? o_.min_confidence : min_confidence;
  FusedMask out;
  // 1. Segmenter persons (box-only detections enter as their box).
  for (const DetectedInstance& inst : det.instances) {  // ascending id
    if (inst.confidence < threshold || !o_.person_class_ids.count(inst.class_id)) continue;
    PersonMask pm;
    pm.detection_id = inst.id;
    if (inst.has_mask && !det.instance_ids.empty()) {
      if (det.instance_ids.size() != size_)
        throw InputError(source, "mask size differs from the camera at frame " + det.stamp_text);
      pm.mask = det.MaskOf(inst.id);
    } else {
      pm.mask = cv::Mat::zeros(size_, CV_8U);
      const cv::Rect box = cv::Rect(cv::Point(int(inst.x_min), int(inst.y_min)),
                                    cv::Point(int(inst.x_max) + 1, int(inst.y_max) + 1)) & cv::Rect(cv::Point(), size_);
      pm.mask(box).setTo(255);
    }
    pm.box = cv::boundingRect(pm.mask);  // E11: the mask's tight box
    if (pm.box.area() == 0) continue;
    out.persons.push_back(std::move(pm));
  }
  // 2. Missed-segmentation compensation (tracks always; pastes only when enabled).
  out.comp = compensator_.Process(stamp, out.persons, o_.compensation);
  out.origin = cv::Mat::zeros(size_, CV_8U);
  out.origin.setTo(kCompensation, out.comp.compensated);
  out.origin.setTo(kSegmenter, out.comp.mask & ~out.comp.compensated);
  out.mask = out.comp.mask.clone();
  // 3. Depth fusion over every person box after compensation; M_sd = M_s OR M_d^1 OR ...
  if (o_.depth_fusion && !out.comp.boxes.empty()) {
    const std::vector<cv::Point> samples = StratifiedSamples(size_, o_.depth, rng_);
    for (const cv::Rect& box : out.comp.boxes) {
      cv::Mat fused = cv::Mat::zeros(size_, CV_8U);
      BoxFusion bf;
      bf.box = box;
      bf.range = FuseBoxDepth(depth_m, box, samples, o_.depth, &fused);
      const cv::Mat added = fused & ~out.mask;
      bf.added_px = cv::countNonZero(added);
      out.origin.setTo(kDepthFusion, added);
      out.mask |= fused;
      out.fusion.push_back(bf);
    }
  }
  // 4. Dilation, (2 * dilation_size + 1)^2 rectangle.
  if (o_.dilation_size > 0 && cv::countNonZero(out.mask) > 0) {
    const int k = 2 * o_.dilation_size + 1;
    cv::Mat dilated;
    cv::dilate(out.mask, dilated, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
    out.origin.setTo(kDilation, dilated & ~out.mask);
    out.mask = dilated;
  }
  return out;
}

}  // namespace dynref::blur
