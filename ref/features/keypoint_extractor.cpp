// Extractor factory; see keypoint_extractor.h.
#include "features/keypoint_extractor.h"

#include "core/error.h"
#include "features/onnx_extractor.h"
#include "features/sift_extractor.h"

namespace dynref::features {
namespace {

// ORB behind the interface.
class OrbPlugin : public KeypointExtractor {
 public:
  explicit OrbPlugin(const OrbOptions& o) : orb_(o) {}
  void Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors) override {
    orb_.Extract(grey, keys, descriptors);
  }
  DescriptorProfile profile() const override {
    DescriptorProfile p;  // the defaults are ORBmatcher's
    p.n_levels = orb_.options().n_levels;
    p.scale_factor = orb_.options().scale_factor;
    return p;
  }
  void set_threads(int n) override { orb_.set_threads(n); }

 private:
  OrbExtractor orb_;
};

// Overrides the profile's gates with the configured ones.
class GateOverride : public KeypointExtractor {
 public:
  GateOverride(std::unique_ptr<KeypointExtractor> inner, const ExtractorOptions& o) : inner_(std::move(inner)), o_(o) {}
  void Extract(const cv::Mat& grey, std::vector<cv::KeyPoint>* keys, cv::Mat* descriptors) override {
    inner_->Extract(grey, keys, descriptors);
  }
  DescriptorProfile profile() const override {
    DescriptorProfile p = inner_->profile();
    if (o_.th_low > 0) p.th_low = static_cast<float>(o_.th_low);
    if (o_.th_high > 0) p.th_high = static_cast<float>(o_.th_high);
    if (o_.th_reloc > 0) p.th_reloc = static_cast<float>(o_.th_reloc);
    return p;
  }
  void set_threads(int n) override { inner_->set_threads(n); }

 private:
  std::unique_ptr<KeypointExtractor> inner_;
  ExtractorOptions o_;
};

}  // namespace

void ExtractorOptions::Check() const {
  if (type != "orb" && type != "sift" && type != "onnx")
    throw InputError("backbone.features", "must be orb, sift or onnx, got '" + type + "'");
  orb.Check();
  if (sift.n_features < 1 || onnx.n_features < 1) throw InputError("backbone.n_features", "must be >= 1");
  if (onnx.nms_radius < 0 || onnx.border < 0) throw InputError("backbone.onnx_nms_radius", "radius and border must be >= 0");
}

std::unique_ptr<KeypointExtractor> MakeExtractor(const ExtractorOptions& o) {
  o.Check();
  std::unique_ptr<KeypointExtractor> e;
  if (o.type == "orb") e = std::make_unique<OrbPlugin>(o.orb);
  else if (o.type == "sift") e = std::make_unique<SiftExtractor>(o.sift);
  else e = std::make_unique<OnnxExtractor>(o.onnx);
  if (o.th_low > 0 || o.th_high > 0 || o.th_reloc > 0) e = std::make_unique<GateOverride>(std::move(e), o);
  e->profile().Check();  // e.g. an override with th_low > th_high
  return e;
}

}  // namespace dynref::features
