// Precomputed sources: a dynref-detections folder (`files:DIR`, `gt`, `gt:MODE`) read through
// DetectionsReader, and the label-PNG importer (`labels:DIR`).
#include "core/error.h"
#include "detect/label_png_import.h"
#include "detect/sources.h"

namespace dynref::detect {
namespace {

void CheckMaskSize(const FrameDetections& f, const cv::Mat& bgr, const std::string& file) {
  if (!bgr.empty() && !f.instance_ids.empty() && f.instance_ids.size() != bgr.size())
    throw InputError(file, "mask is " + std::to_string(f.instance_ids.cols) + "x" +
                               std::to_string(f.instance_ids.rows) + " but the frame is " +
                               std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows));
}

class FolderSource : public DetectionSource {
 public:
  explicit FolderSource(const std::string& dir) : dir_(dir), reader_(dir) {}
  std::string name() const override { return reader_.source().empty() ? "files" : reader_.source(); }
  std::string model_sha256() const override {
    return reader_.model_sha256().empty() ? "-" : reader_.model_sha256();
  }
  bool needs_image() const override { return false; }
  FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) override {
    FrameDetections f = reader_.Read(stamp_text);  // InputError if absent or corrupt
    CheckMaskSize(f, bgr, dir_ + "/" + stamp_text + ".png");
    return f;
  }

 private:
  std::string dir_;
  DetectionsReader reader_;
};

class LabelPngSource : public DetectionSource {
 public:
  explicit LabelPngSource(const std::string& dir) : dir_(dir), table_(ReadLabelTable(dir + "/labels.yaml")) {}
  std::string name() const override { return "labels"; }
  std::string model_sha256() const override { return "-"; }
  bool needs_image() const override { return false; }
  FrameDetections Detect(const cv::Mat& bgr, const std::string& stamp_text) override {
    const std::string png = dir_ + "/" + stamp_text + ".png";
    FrameDetections f = ReadLabelPng(table_, png, stamp_text);
    CheckMaskSize(f, bgr, png);
    return f;
  }

 private:
  std::string dir_;
  LabelTable table_;
};

}  // namespace

std::unique_ptr<DetectionSource> MakeFolderSource(const std::string& dir) {
  return std::make_unique<FolderSource>(dir);
}

std::unique_ptr<DetectionSource> MakeLabelPngSource(const std::string& dir) {
  return std::make_unique<LabelPngSource>(dir);
}

}  // namespace dynref::detect
