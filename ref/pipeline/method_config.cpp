// Method config loading; see method_config.h.
#include "pipeline/method_config.h"

#include <yaml-cpp/yaml.h>

#include <sys/stat.h>

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

// yaml-cpp keeps both entries of a key given twice (lookups see the first, iteration both):
// refuse it, naming the line of the second.
void RejectDuplicateKeys(const YAML::Node& map, const std::string& file, const std::string& where) {
  std::map<std::string, int> seen;
  for (const auto& kv : map) {
    const std::string k = kv.first.as<std::string>();
    const auto [it, inserted] = seen.emplace(k, LineOf(kv.first));
    if (!inserted)
      throw InputError(file, LineOf(kv.first), where + "duplicate key '" + k +
                                                   "' (first given at line " +
                                                   std::to_string(it->second) + ")");
  }
}

Param ReadParam(const YAML::Node& node, const std::string& key, const std::string& file) {
  Param p;
  p.file = file;
  p.line = LineOf(node);
  if (!node.IsMap()) throw InputError(file, p.line, key + ": expected {value: ..., source: \"...\"}");
  RejectDuplicateKeys(node, file, key + ": ");
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
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, "method config not found");
  if (!S_ISREG(st.st_mode)) throw InputError(path, "method config is not a regular file");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open method config");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, std::string("YAML: ") + e.msg);
  } catch (const std::ios_base::failure&) {
    throw InputError(path, "cannot read method config");
  }
  if (!root.IsMap()) throw InputError(path, "top level must be a map (method, backbone, stages)");
  RejectDuplicateKeys(root, path, "");
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
    RejectDuplicateKeys(b, path, "backbone: ");
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
  // Integer keys: the range is checked on the number before the int conversion (a value past
  // the int range would wrap, and some size allocations), then AsInt() checks it is integral.
  auto int_in = [&](const char* key, double lo, double hi) {
    const Param& p = bb.params.at(key);
    const double v = p.AsDouble();
    if (!(v >= lo && v <= hi))
      bad(key, "must be in " + std::to_string(static_cast<int64_t>(lo)) + ".." +
                   std::to_string(static_cast<int64_t>(hi)) + ", got " + p.value);
    (void)p.AsInt();
  };
  // The ORB extractor reserves 10 * n_features candidate keypoints per level (int arithmetic)
  // and the frame sizes its keypoint/descriptor arrays by it; 100000 is 100x the ORB-SLAM2
  // default, far more corners than a 640x480 pyramid yields.
  int_in("n_features", 1, 100000);
  if (!(bb.scale_factor() > 1)) bad("scale_factor", "must be > 1");
  // Sizes the image pyramid (one image and scale per level); 16 as OrbOptions::Check.
  int_in("n_levels", 1, 16);
  // FAST thresholds are intensity differences on 8-bit images: nothing passes above 255.
  int_in("ini_th_fast", 1, 255);
  int_in("min_th_fast", 1, 255);
  if (bb.min_th_fast() > bb.ini_th_fast())
    bad("min_th_fast", "need 1 <= min_th_fast <= ini_th_fast");
  // Compared with the number of features with depth (at most n_features, bounded above).
  int_in("min_init_points", 1, 100000);
  // Added to frame indices (int) in the keyframe and relocalisation decisions; 100000 frames
  // (55 min at 30 fps) keeps the sums far from overflow.
  int_in("max_frames", 1, 100000);
  // Number of relocalisation candidate keyframes, each tried with a RANSAC.
  int_in("reloc_recent_keyframes", 1, 100000);
  (void)bb.local_ba();
  (void)bb.keyframe_culling();
  (void)bb.camera_rgb_flag();
  // Read through a double: 2^53 is the largest range in which every integer is exact.
  int_in("seed", 0, 9007199254740992.0);

  if (root["stages"]) {
    const YAML::Node s = root["stages"];
    if (!s.IsSequence()) throw InputError(path, LineOf(s), "stages must be a list");
    std::map<std::string, int> stage_lines;  // no config lists a stage twice: refused
    for (const auto& st : s) {
      if (!st.IsMap()) throw InputError(path, LineOf(st), "a stage must be {name: ..., params: {...}}");
      RejectDuplicateKeys(st, path, "stage: ");
      StageConfig sc;
      for (const auto& kv : st) {
        const std::string k = kv.first.as<std::string>();
        if (k != "name" && k != "params")
          throw InputError(path, LineOf(kv.first), "unknown stage key '" + k + "' (expected name, params)");
      }
      if (!st["name"] || !st["name"].IsScalar()) throw InputError(path, LineOf(st), "stage without name");
      sc.name = st["name"].as<std::string>();
      const auto [first, inserted] = stage_lines.emplace(sc.name, LineOf(st));
      if (!inserted)
        throw InputError(path, LineOf(st), "stage '" + sc.name + "' listed twice (first at line " +
                                               std::to_string(first->second) + ")");
      sc.params.stage_name = sc.name;
      sc.params.file = path;
      sc.params.line = LineOf(st);
      if (st["params"]) {
        if (!st["params"].IsMap()) throw InputError(path, LineOf(st["params"]), "params must be a map");
        RejectDuplicateKeys(st["params"], path, sc.name + ": ");
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
