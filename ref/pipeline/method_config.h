// Method configuration (configs/<method>.yaml): every parameter is {value: X, source: "..."}
// where source is "paper Sec. ..." or "not stated: chosen because ...". Structure:
//   method: NAME
//   backbone: {n_features: {value: 1000, source: "..."}, ...}   (keys of BackboneConfig)
//   stages: [ {name: "sgdo.mask", params: {key: {value: ..., source: "..."}}}, ... ]
// Unknown keys, duplicate keys, a stage listed twice and out-of-range backbone values are
// InputErrors naming the file and line. Backbone keys left out take the
// ORB-SLAM2 default and are recorded with the source "default: ORB-SLAM2 ...".
#pragma once
#include <string>
#include <vector>

#include "pipeline/stage.h"

namespace dynref {

struct BackboneConfig {
  std::map<std::string, Param> params;  // every backbone key, resolved (defaults filled in)
  int n_features() const { return static_cast<int>(params.at("n_features").AsInt()); }
  double scale_factor() const { return params.at("scale_factor").AsDouble(); }
  int n_levels() const { return static_cast<int>(params.at("n_levels").AsInt()); }
  int ini_th_fast() const { return static_cast<int>(params.at("ini_th_fast").AsInt()); }
  int min_th_fast() const { return static_cast<int>(params.at("min_th_fast").AsInt()); }
  int min_init_points() const { return static_cast<int>(params.at("min_init_points").AsInt()); }
  int max_frames() const { return static_cast<int>(params.at("max_frames").AsInt()); }
  int reloc_recent_keyframes() const { return static_cast<int>(params.at("reloc_recent_keyframes").AsInt()); }
  bool local_ba() const { return params.at("local_ba").AsBool(); }
  bool keyframe_culling() const { return params.at("keyframe_culling").AsBool(); }
  uint64_t seed() const { return static_cast<uint64_t>(params.at("seed").AsInt()); }
  bool camera_rgb_flag() const { return params.at("camera_rgb_flag").AsBool(); }
};

struct StageConfig {
  std::string name;
  ParamMap params;
};

struct MethodConfig {
  std::string path;
  std::string method;
  BackboneConfig backbone;
  std::vector<StageConfig> stages;
  // Fully resolved configuration as JSON text (sorted keys; every value with its source).
  std::string ToJson() const;
};

// Reads and validates a config file (InputError naming file:line on any problem).
MethodConfig LoadMethodConfig(const std::string& path);
// configs/<method>.yaml in the source tree (DYNREF_SOURCE_DIR at compile time).
std::string MethodConfigPath(const std::string& method);

}  // namespace dynref
