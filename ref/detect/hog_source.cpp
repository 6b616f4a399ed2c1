// `hog` source: OpenCV's HOG + linear SVM people detector (Dalal & Triggs 2005, the default
// 64x128 people model of cv::HOGDescriptor::getDefaultPeopleDetector), the no-network
// fallback. Boxes only; confidence = logistic(SVM margin), so margin 0 maps to 0.5.
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>
#include <cmath>
#include <tuple>

#include "detect/sources.h"
#include "core/stable_sort.h"

namespace dynref::detect {
namespace {

class HogSource : public DetectionSource {
 public:
  explicit HogSource(const DetectSourceOptions& options) : options_(options) {
    hog_.setSVMDetector(cv::HOGDescriptor::getDefaultPeopleDetector());
    threshold_ = options.confidence_threshold >= 0 ? options.confidence_threshold : 0.5;
  }
  std::string name() const override { return "hog"; }
  std::string model_sha256() const override { return "-"; }
  bool needs_image() const override { return true; }

  FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) override {
    RequireBgrImage(bgr, stamp_text, "hog");
    // An image smaller than the detection window (64x128) holds no window position: no
    // detections (issue 37). OpenCV's pyramid only shrinks the image (scale >= 1), so nothing is
    // lost by not upscaling, and OpenCV 4.6's detectMultiScale always evaluates its first level
    // even when the window does not fit, reading and writing out of bounds (heap corruption on
    // 16x16 / 32x32, an assertion on 48x64).
    if (bgr.cols < hog_.winSize.width || bgr.rows < hog_.winSize.height)
      return CandidatesToFrame({}, stamp_text, CocoClassNames());
    std::vector<cv::Rect> found;
    std::vector<double> weights;
    // OpenCV defaults: stride 8, scale step 1.05, groups of >= 2 raw hits merged.
    hog_.detectMultiScale(bgr, found, weights, /*hitThreshold=*/0, cv::Size(8, 8), cv::Size(0, 0),
                          /*scale=*/1.05, /*groupThreshold=*/2);
    std::vector<Candidate> candidates;
    for (size_t i = 0; i < found.size(); ++i) {
      const double w = i < weights.size() ? weights[i] : 0.0;
      Candidate c;
      c.class_id = 0;  // person
      c.score = 1.0 / (1.0 + std::exp(-w));
      c.x_min = found[i].x;
      c.y_min = found[i].y;
      c.x_max = found[i].x + found[i].width;
      c.y_max = found[i].y + found[i].height;
      c.anchor = int(i);
      ClipBox(c, bgr.cols, bgr.rows);
      if (c.score >= threshold_ && c.x_max > c.x_min && c.y_max > c.y_min) candidates.push_back(c);
    }
    // Descending confidence, ties by position (grouping output order is not a contract).
    StableSortBy(candidates, [](const Candidate& c) { return std::make_tuple(-c.score, c.y_min, c.x_min, c.x_max, c.y_max); });
    if (int(candidates.size()) > options_.max_detections) candidates.resize(options_.max_detections);
    return CandidatesToFrame(candidates, stamp_text, CocoClassNames());
  }

 private:
  DetectSourceOptions options_;
  cv::HOGDescriptor hog_;
  double threshold_ = 0.5;
};

}  // namespace

std::unique_ptr<DetectionSource> MakeHogSource(const DetectSourceOptions& options) {
  return std::make_unique<HogSource>(options);
}

}  // namespace dynref::detect
