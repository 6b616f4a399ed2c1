#include "synth/montage.h"

#include <opencv2/imgproc.hpp>
#include <fstream>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/mask_format.h"
#include "io/image_file.h"

namespace dynref::synth {
namespace {

std::string PresetOf(const std::string& dir) {
  std::ifstream in(dir + "/synth.yaml");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("preset: ", 0) == 0) return line.substr(8);
  return dir;
}

cv::Vec3b IdColour(int id) {
  static const cv::Vec3b kColours[6] = {{255, 80, 40}, {40, 200, 255}, {60, 255, 60},
                                        {255, 60, 255}, {40, 140, 255}, {255, 255, 60}};
  return kColours[id % 6];
}

cv::Mat Overlay(const cv::Mat& rgb, const FrameDetections& gt, const cv::Mat& motion) {
  cv::Mat out = rgb.clone();
  for (const auto& d : gt.instances) {
    const cv::Mat mask = gt.MaskOf(d.id);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    if (d.class_id == 0) {
      cv::Mat tint(out.size(), CV_8UC3, cv::Scalar(IdColour(d.id)[0], IdColour(d.id)[1], IdColour(d.id)[2]));
      cv::Mat blended;
      cv::addWeighted(out, 0.72, tint, 0.28, 0, blended);
      blended.copyTo(out, mask);
      cv::drawContours(out, contours, -1, cv::Scalar(IdColour(d.id)[0], IdColour(d.id)[1], IdColour(d.id)[2]), 2);
    } else if (d.class_id >= 0 || d.class_name == "box") {
      cv::drawContours(out, contours, -1, cv::Scalar(0, 220, 255), 1);
    }
  }
  if (!motion.empty()) {
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(motion.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    cv::drawContours(out, contours, -1, cv::Scalar(0, 0, 255), 2);
  }
  return out;
}

}  // namespace

void MontageOptions::Check() const {
  // Named after the synth-montage options in ref/cli/cmd_synth.cpp.
  if (frames_per_row < 1 || frames_per_row > 8)
    throw InputError("--frames-per-row", "must be in 1..8 (got " + std::to_string(frames_per_row) + ")");
  if (tile_width < 64 || tile_width > 640)
    throw InputError("--tile-width", "must be in 64..640 (got " + std::to_string(tile_width) + ")");
}

void WriteMontage(const std::vector<std::string>& dirs, const std::string& out_png, const MontageOptions& opt) {
  opt.Check();
  if (dirs.empty()) throw InputError("montage", "no sequence folders given");
  const int tw = opt.tile_width, th = tw * 3 / 4;
  const int cols = opt.frames_per_row + 1;
  cv::Mat canvas(th * int(dirs.size()), tw * cols, CV_8UC3, cv::Scalar(0, 0, 0));
  for (size_t r = 0; r < dirs.size(); ++r) {
    const DetectionsReader gt(dirs[r] + "/gt");
    const auto stamps = gt.Stamps();
    if (stamps.empty()) throw InputError(dirs[r] + "/gt/index.txt", "no frames");
    for (int c = 0; c < opt.frames_per_row; ++c) {
      const size_t k = std::min(stamps.size() - 1, stamps.size() * size_t(2 * c + 1) / size_t(2 * opt.frames_per_row));
      const std::string& stamp = stamps[k];
      const cv::Mat rgb = dynref::ImageRead(dirs[r] + "/rgb/" + stamp + ".png", cv::IMREAD_COLOR);
      if (rgb.empty()) throw InputError(dirs[r] + "/rgb/" + stamp + ".png", "missing or unreadable");
      const cv::Mat motion = dynref::ImageRead(dirs[r] + "/gt/motion/" + stamp + ".png", cv::IMREAD_GRAYSCALE);
      cv::Mat tile;
      cv::resize(Overlay(rgb, gt.Read(stamp), motion), tile, cv::Size(tw, th), 0, 0, cv::INTER_AREA);
      tile.copyTo(canvas(cv::Rect(c * tw, int(r) * th, tw, th)));
      if (c == opt.frames_per_row / 2) {  // depth of the middle frame
        std::ifstream assoc(dirs[r] + "/associations.txt");
        std::string a, ap, d, dp;
        while (assoc >> a >> ap >> d >> dp)
          if (a == stamp) break;
        cv::Mat depth = dynref::ImageRead(dirs[r] + "/" + dp, cv::IMREAD_UNCHANGED), d8, colour;
        if (!depth.empty()) {
          depth.convertTo(d8, CV_8U, 255.0 / (4.5 * 5000.0));
          cv::applyColorMap(d8, colour, cv::COLORMAP_JET);
          colour.setTo(cv::Scalar(0, 0, 0), depth == 0);
          cv::resize(colour, tile, cv::Size(tw, th), 0, 0, cv::INTER_AREA);
          tile.copyTo(canvas(cv::Rect(opt.frames_per_row * tw, int(r) * th, tw, th)));
        }
      }
    }
    cv::putText(canvas, PresetOf(dirs[r]), cv::Point(6, int(r) * th + 18), cv::FONT_HERSHEY_SIMPLEX, 0.55,
                cv::Scalar(0, 0, 0), 3);
    cv::putText(canvas, PresetOf(dirs[r]), cv::Point(6, int(r) * th + 18), cv::FONT_HERSHEY_SIMPLEX, 0.55,
                cv::Scalar(255, 255, 255), 1);
  }
  const std::string tmp = TempPathFor(out_png) + ".png";
  if (!dynref::ImageWrite(tmp, canvas, {cv::IMWRITE_PNG_COMPRESSION, 9})) throw std::runtime_error("cannot write " + tmp);
  AtomicRename(tmp, out_png);
}

}  // namespace dynref::synth
