#include "detect/label_png_import.h"

#include <yaml-cpp/yaml.h>
#include <opencv2/imgproc.hpp>
#include <algorithm>

#include "core/error.h"
#include "io/coco_classes.h"
#include "io/image_file.h"

namespace dynref::detect {

LabelTable ReadLabelTable(const std::string& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::BadFile&) {
    throw InputError(yaml_path, "cannot open label table (expected labels.yaml next to the label PNGs)");
  } catch (const YAML::Exception& e) {
    throw InputError(yaml_path, e.mark.line + 1, "malformed YAML: " + e.msg);
  }
  LabelTable t;
  try {
    if (root["png_kind"]) {
      const std::string kind = root["png_kind"].as<std::string>();
      if (kind != "instance" && kind != "semantic")
        throw InputError(yaml_path, root["png_kind"].Mark().line + 1, "png_kind must be 'instance' or 'semantic'");
      t.semantic = kind == "semantic";
    }
    if (root["confidence"]) t.confidence = root["confidence"].as<double>();
    if (!(t.confidence >= 0 && t.confidence <= 1)) throw InputError(yaml_path, "confidence must be in [0, 1]");
    if (root["min_area_px"]) t.min_area_px = root["min_area_px"].as<int>();
    const YAML::Node labels = root["labels"];
    if (!labels || !labels.IsMap() || labels.size() == 0)
      throw InputError(yaml_path, "needs a non-empty 'labels' map (pixel value: class name)");
    for (const auto& kv : labels) {
      const int value = kv.first.as<int>();
      if (value < 1 || value > 65535)
        throw InputError(yaml_path, kv.first.Mark().line + 1, "label values must be in 1..65535");
      std::string name = kv.second.as<std::string>();
      std::replace(name.begin(), name.end(), ' ', '_');
      if (name.empty()) throw InputError(yaml_path, kv.first.Mark().line + 1, "empty class name");
      t.labels[value] = name;
    }
  } catch (const YAML::Exception& e) {
    throw InputError(yaml_path, e.mark.line + 1, "bad value: " + e.msg);
  }
  return t;
}

FrameDetections ReadLabelPng(const LabelTable& table, const std::string& png_path,
                             const std::string& stamp_text) {
  const cv::Mat raw = dynref::ImageRead(png_path, cv::IMREAD_UNCHANGED);
  if (raw.empty()) throw InputError(png_path, "missing or corrupt label PNG");
  if (raw.channels() != 1 || (raw.depth() != CV_8U && raw.depth() != CV_16U))
    throw InputError(png_path, "label PNG must be 8- or 16-bit single channel");
  cv::Mat labels;
  raw.convertTo(labels, CV_32S);
  // Values present, ascending.
  std::map<int, int> present;
  for (int y = 0; y < labels.rows; ++y)
    for (int x = 0; x < labels.cols; ++x)
      if (labels.at<int>(y, x) != 0) ++present[labels.at<int>(y, x)];
  FrameDetections frame;
  frame.stamp_text = stamp_text;
  cv::Mat ids = cv::Mat::zeros(labels.size(), CV_16U);
  int next_id = 1;
  for (const auto& [value, count] : present) {
    auto it = table.labels.find(value);
    if (it == table.labels.end())
      throw InputError(png_path, "pixel value " + std::to_string(value) + " is not in labels.yaml");
    const cv::Mat region_of_value = labels == value;
    cv::Mat comp, stats, centroids;
    int n_regions = 1;
    if (table.semantic) {
      n_regions = cv::connectedComponentsWithStats(region_of_value, comp, stats, centroids, 8, CV_32S) - 1;
    } else {
      comp = cv::Mat::zeros(labels.size(), CV_32S);
      comp.setTo(1, region_of_value);
    }
    for (int r = 1; r <= n_regions; ++r) {
      const cv::Mat mask = comp == r;
      if (cv::countNonZero(mask) < table.min_area_px) continue;
      if (next_id > 65535) throw InputError(png_path, "more than 65535 instances");
      const cv::Rect box = cv::boundingRect(mask);
      DetectedInstance d;
      d.id = next_id++;
      d.class_name = it->second;
      d.class_id = CocoClassId(d.class_name);
      d.confidence = table.confidence;
      d.x_min = box.x;
      d.y_min = box.y;
      d.x_max = box.x + box.width - 1;  // inclusive extreme pixels, as MASK_FORMAT.md says (issue 20 item 11)
      d.y_max = box.y + box.height - 1;
      d.has_mask = true;
      ids.setTo(d.id, mask);
      frame.instances.push_back(d);
    }
  }
  if (!frame.instances.empty()) frame.instance_ids = ids;
  return frame;
}

}  // namespace dynref::detect
