#include "detect/temporal_source.h"

#include "io/stamped_list.h"

namespace dynref::detect {
namespace {

class TemporalSource : public DetectionSource {
 public:
  TemporalSource(std::unique_ptr<DetectionSource> inner, const TemporalOptions& options, cv::Size image_size)
      : inner_(std::move(inner)), linker_(options, image_size) {}
  std::string name() const override { return inner_->name(); }
  std::string model_sha256() const override { return inner_->model_sha256(); }
  bool needs_image() const override { return inner_->needs_image(); }

  FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) override {
    // The stamp as rgb.txt spells it, parsed as the sequence reader parses it.
    const double stamp_s = ParseNumberField(stamp_text, "frame " + stamp_text, 0, "rgb stamp");
    return linker_.Process(inner_->Detect(bgr, stamp_text), stamp_s, nullptr);
  }

 private:
  std::unique_ptr<DetectionSource> inner_;
  TemporalLinker linker_;
};

}  // namespace

std::unique_ptr<DetectionSource> WithTemporalLinks(std::unique_ptr<DetectionSource> inner,
                                                   const TemporalOptions& options, cv::Size image_size) {
  options.Check();
  if (options.max_gap == 0) return inner;
  return std::make_unique<TemporalSource>(std::move(inner), options, image_size);
}

}  // namespace dynref::detect
