// Method config loading; see method_config.h.
#include "pipeline/method_config.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace dynref {
namespace {

struct Default {
  const char* key;
  const char* value;
  const char* source;
};

// ORB-SLAM2 defaults (Examples/RGB-D/TUM*.yaml and src/Tracking.cc).
const Default kBackboneDefaults[] = {
    {"n_features", "1000", "default: ORB-SLAM2 TUM RGB-D settings ORBextractor.nFeatures"},
    {"scale_factor", "1.2", "default: ORB-SLAM2 ORBextractor.scaleFactor"},
    {"n_levels", "8", "default: ORB-SLAM2 ORBextractor.nLevels"},
    {"ini_th_fast", "20", "default: ORB-SLAM2 ORBextractor.iniThFAST"},
    {"min_th_fast", "7", "default: ORB-SLAM2 ORBextractor.minThFAST"},
    {"min_init_points", "500", "default: ORB-SLAM2 Tracking::StereoInitialization N > 500"},
    {"max_frames", "30", "default: ORB-SLAM2 mMaxFrames = Camera.fps (30)"},
    {"reloc_recent_keyframes", "10",
     "not stated: dynref has no BoW database; relocalisation tries the 10 most recent keyframes"},
    {"local_ba", "true", "default: ORB-SLAM2 local mapping runs local BA"},
    {"keyframe_culling", "true", "default: ORB-SLAM2 LocalMapping::KeyFrameCulling"},
    {"seed", "1", "not stated: seed of dynref's named RNG streams (relocalisation RANSAC)"},
    {"camera_rgb_flag", "true",
     "default: ORB-SLAM2 TUM1-3.yaml Camera.RGB: 1 applied to cv::imread's BGR images "
     "(Tracking::GrabImageRGBD converts with CV_RGB2GRAY, so blue gets red's weight); "
     "false = luminance of the true colours (COLOR_BGR2GRAY)"},
};

int LineOf(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

Param ReadParam(const YAML::Node& node, const std::string& key, const std::string& file) {
  Param p;
  p.file = file;
  p.line = LineOf(node);
  if (!node.IsMap()) throw InputError(file, p.line, key + ": expected {value: ..., source: \"...\"}");
  for (const auto& kv : node) {
    const std::string k = kv.first.as<std::string>();
    if (k != "value" && k != "source")
      throw InputError(file, LineOf(kv.first), key + ": unknown key '" + k + "' (expected value, source)");
  }
  if (!node["value"]) throw InputError(file, p.line, key + ": missing value");
  if (!node["source"] || !node["source"].IsScalar() || node["source"].as<std::string>().empty())
    throw InputError(file, p.line, key + ": missing source (\"paper Sec. ...\" or \"not stated: ...\")");
  p.source = node["source"].as<std::string>();
  const YAML::Node v = node["value"];
  if (v.IsScalar()) {
    p.value = v.as<std::string>();
  } else if (v.IsSequence()) {
    for (const auto& e : v) {
      if (!e.IsScalar()) throw InputError(file, LineOf(e), key + ": list values must be scalars");
      p.list.push_back(e.as<std::string>());
    }
  } else {
    throw InputError(file, p.line, key + ": value must be a scalar or a list of scalars");
  }
  return p;
}

nlohmann::json ParamJson(const Param& p) {
  nlohmann::json j;
  if (p.list.empty()) {
    j["value"] = p.value;
  } else {
    j["value"] = p.list;
  }
  j["source"] = p.source;
  return j;
}

}  // namespace

std::string MethodConfigPath(const std::string& method) {
  return std::string(DYNREF_SOURCE_DIR) + "/configs/" + method + ".yaml";
}

MethodConfig LoadMethodConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open method config");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, std::string("YAML: ") + e.msg);
  }
  if (!root.IsMap()) throw InputError(path, "top level must be a map (method, backbone, stages)");
  MethodConfig cfg;
  cfg.path = path;
  for (const auto& kv : root) {
    const std::string k = kv.first.as<std::string>();
    if (k != "method" && k != "backbone" && k != "stages")
      throw InputError(path, LineOf(kv.first), "unknown key '" + k + "' (expected method, backbone, stages)");
  }
  if (!root["method"] || !root["method"].IsScalar()) throw InputError(path, "missing 'method: NAME'");
  cfg.method = root["method"].as<std::string>();
  std::map<std::string, Param> given;
  if (root["backbone"]) {
    const YAML::Node b = root["backbone"];
    if (!b.IsMap()) throw InputError(path, LineOf(b), "backbone must be a map");
    for (const auto& kv : b) {
      const std::string k = kv.first.as<std::string>();
      bool known = false;
      for (const Default& d : kBackboneDefaults) known = known || k == d.key;
      if (!known) throw InputError(path, LineOf(kv.first), "unknown backbone key '" + k + "'");
      given[k] = ReadParam(kv.second, k, path);
    }
  }
  for (const Default& d : kBackboneDefaults) {
    auto it = given.find(d.key);
    if (it != given.end()) {
      cfg.backbone.params[d.key] = it->second;
    } else {
      Param p;
      p.value = d.value;
      p.source = d.source;
      p.file = path;
      cfg.backbone.params[d.key] = p;
    }
  }
  // Validate backbone values (typed access throws InputError naming file:line).
  const BackboneConfig& bb = cfg.backbone;
  auto bad = [&](const char* key, const std::string& what) {
    const Param& p = bb.params.at(key);
    throw InputError(p.file, p.line, std::string("backbone.") + key + ": " + what);
  };
  if (bb.n_features() < 1) bad("n_features", "must be >= 1");
  if (!(bb.scale_factor() > 1)) bad("scale_factor", "must be > 1");
  if (bb.n_levels() < 1 || bb.n_levels() > 16) bad("n_levels", "must be in 1..16");
  if (bb.min_th_fast() < 1 || bb.min_th_fast() > bb.ini_th_fast()) bad("min_th_fast", "need 1 <= min_th_fast <= ini_th_fast");
  if (bb.min_init_points() < 1) bad("min_init_points", "must be >= 1");
  if (bb.max_frames() < 1) bad("max_frames", "must be >= 1");
  if (bb.reloc_recent_keyframes() < 1) bad("reloc_recent_keyframes", "must be >= 1");
  (void)bb.local_ba();
  (void)bb.keyframe_culling();
  (void)bb.camera_rgb_flag();
  if (bb.params.at("seed").AsInt() < 0) bad("seed", "must be >= 0");

  if (root["stages"]) {
    const YAML::Node s = root["stages"];
    if (!s.IsSequence()) throw InputError(path, LineOf(s), "stages must be a list");
    for (const auto& st : s) {
      if (!st.IsMap()) throw InputError(path, LineOf(st), "a stage must be {name: ..., params: {...}}");
      StageConfig sc;
      for (const auto& kv : st) {
        const std::string k = kv.first.as<std::string>();
        if (k != "name" && k != "params")
          throw InputError(path, LineOf(kv.first), "unknown stage key '" + k + "' (expected name, params)");
      }
      if (!st["name"] || !st["name"].IsScalar()) throw InputError(path, LineOf(st), "stage without name");
      sc.name = st["name"].as<std::string>();
      sc.params.stage_name = sc.name;
      sc.params.file = path;
      sc.params.line = LineOf(st);
      if (st["params"]) {
        if (!st["params"].IsMap()) throw InputError(path, LineOf(st["params"]), "params must be a map");
        for (const auto& kv : st["params"]) {
          const std::string k = kv.first.as<std::string>();
          sc.params.params[k] = ReadParam(kv.second, sc.name + "." + k, path);
        }
      }
      cfg.stages.push_back(std::move(sc));
    }
  }
  return cfg;
}

std::string MethodConfig::ToJson() const {
  nlohmann::json j;
  j["method"] = method;
  j["config_file"] = path;
  nlohmann::json b = nlohmann::json::object();
  for (const auto& [k, p] : backbone.params) b[k] = ParamJson(p);
  j["backbone"] = b;
  nlohmann::json st = nlohmann::json::array();
  for (const StageConfig& s : stages) {
    nlohmann::json sj;
    sj["name"] = s.name;
    nlohmann::json pj = nlohmann::json::object();
    for (const auto& [k, p] : s.params.params) pj[k] = ParamJson(p);
    sj["params"] = pj;
    st.push_back(sj);
  }
  j["stages"] = st;
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);  // invalid UTF-8 -> U+FFFD
}

}  // namespace dynref
