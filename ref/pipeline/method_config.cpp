// Method config loading; see method_config.h.
#include "pipeline/method_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>

#include <sys/stat.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/resources.h"

namespace dynref {
namespace {

int LineOf(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

// A map key as text; a key that is itself a map or a list ("{a: 1}: 2") is refused by name
// (yaml-cpp would throw a bare "bad conversion" from as<std::string>()).
std::string KeyText(const YAML::Node& key, const std::string& file) {
  if (!key.IsScalar()) throw InputError(file, LineOf(key), "a key must be a plain name, not a map or a list");
  return key.as<std::string>();
}

// yaml-cpp keeps both entries of a key given twice (lookups see the first, iteration both):
// refuse it, naming the line of the second.
void RejectDuplicateKeys(const YAML::Node& map, const std::string& file, const std::string& where) {
  std::map<std::string, int> seen;
  for (const auto& kv : map) {
    const std::string k = KeyText(kv.first, file);
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
  p.name = key;
  if (!node.IsMap()) throw InputError(file, p.line, key + ": expected {value: ..., source: \"...\"}");
  RejectDuplicateKeys(node, file, key + ": ");
  for (const auto& kv : node) {
    const std::string k = KeyText(kv.first, file);
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

MethodConfig ParseMethodConfig(const YAML::Node& root, const std::string& path) {
  if (!root.IsMap()) throw InputError(path, "top level must be a map (method, backbone, stages)");
  RejectDuplicateKeys(root, path, "");
  MethodConfig cfg;
  cfg.path = path;
  for (const auto& kv : root) {
    const std::string k = KeyText(kv.first, path);
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
      const std::string k = KeyText(kv.first, path);
      bool known = false;
      for (const BackboneKeyInfo& d : BackboneKeys()) known = known || k == d.key;
      if (!known) throw InputError(path, LineOf(kv.first), "unknown backbone key '" + k + "'");
      given[k] = ReadParam(kv.second, "backbone." + k, path);
    }
  }
  cfg.backbone = ResolveBackbone(given, path, &cfg.backbone_params);

  if (root["stages"]) {
    const YAML::Node s = root["stages"];
    if (!s.IsSequence()) throw InputError(path, LineOf(s), "stages must be a list");
    std::map<std::string, int> stage_lines;  // no config lists a stage twice: refused
    for (const auto& st : s) {
      if (!st.IsMap()) throw InputError(path, LineOf(st), "a stage must be {name: ..., params: {...}}");
      RejectDuplicateKeys(st, path, "stage: ");
      StageConfig sc;
      for (const auto& kv : st) {
        const std::string k = KeyText(kv.first, path);
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
          const std::string k = KeyText(kv.first, path);
          sc.params.params[k] = ReadParam(kv.second, sc.name + "." + k, path);
        }
      }
      cfg.stages.push_back(std::move(sc));
    }
  }
  return cfg;
}

}  // namespace

std::string MethodConfigPath(const std::string& method) {
  // Method names may use '-' (mgd-nd); config files use '_' (configs/mgd_nd.yaml).
  std::string file = method;
  std::replace(file.begin(), file.end(), '-', '_');
  return ResourcePath("configs/" + file + ".yaml");  // core/resources.h: installed or source tree
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
  try {
    return ParseMethodConfig(root, path);
  } catch (const YAML::Exception& e) {
    // Backstop: any conversion the checks above did not foresee still names file and line.
    throw InputError(path, e.mark.line >= 0 ? e.mark.line + 1 : 0, std::string("YAML: ") + e.msg);
  }
}

std::string MethodConfig::ToJson() const {
  nlohmann::json j;
  j["method"] = method;
  j["config_file"] = path;
  nlohmann::json b = nlohmann::json::object();
  for (const auto& [k, p] : backbone_params) b[k] = ParamJson(p);
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

void MethodConfig::SetBackboneParam(const std::string& key, const std::string& value, const std::string& source) {
  auto it = backbone_params.find(key);
  if (it == backbone_params.end()) throw InputError(path, "unknown backbone key '" + key + "'");
  it->second.value = value;
  it->second.list.clear();
  it->second.source = source;
  it->second.defaulted = false;
  backbone = ResolveBackbone(backbone_params, path, &backbone_params);
}

namespace {

// A --set value: "[a, b]" is a list of scalars (YAML flow syntax), anything else one scalar.
void SetValue(Param& p, const std::string& item, const std::string& value) {
  p.value = value;
  p.list.clear();
  if (value.empty() || value.front() != '[') return;
  YAML::Node n;
  try {
    n = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw InputError(item, "a list value must be [a, b, ...]: " + e.msg);
  }
  if (!n.IsSequence()) throw InputError(item, "a list value must be [a, b, ...]");
  for (const auto& e : n) {
    if (!e.IsScalar()) throw InputError(item, "list values must be scalars");
    p.list.push_back(e.as<std::string>());
  }
  p.value.clear();
}

}  // namespace

void MethodConfig::ApplySets(const std::vector<std::string>& items, const std::string& source) {
  for (const std::string& item : items) {
    // The stage name has dots itself (sgdo.depth): the key is after the last one.
    const size_t eq = item.find('=');
    const size_t dot = eq == std::string::npos ? std::string::npos : item.rfind('.', eq);
    if (eq == std::string::npos || dot == std::string::npos || dot == 0 || eq == dot + 1)
      throw InputError("--set", "'" + item + "' is not STAGE.KEY=VALUE (e.g. sgdo.depth.eta=0.05)");
    const std::string where = "--set " + item;
    const std::string stage = item.substr(0, dot), key = item.substr(dot + 1, eq - dot - 1);
    Param* p = nullptr;
    if (stage == "backbone") {
      auto it = backbone_params.find(key);
      if (it == backbone_params.end()) throw InputError(where, "unknown backbone key '" + key + "'");
      p = &it->second;
    } else {
      StageConfig* sc = nullptr;
      for (StageConfig& s : stages) sc = s.name == stage ? &s : sc;
      if (sc == nullptr) throw InputError(where, "no stage " + stage + " in the config " + path);
      auto it = sc->params.params.find(key);
      if (it == sc->params.params.end()) throw InputError(where, "stage " + stage + " has no parameter " + key);
      p = &it->second;
    }
    SetValue(*p, where, item.substr(eq + 1));
    p->source = source;
    p->file = where;  // messages name the --set argument; relative paths are the working directory's
    p->line = 0;
    p->name = stage + "." + key;
    p->defaulted = false;  // set by the user now
  }
  backbone = ResolveBackbone(backbone_params, path, &backbone_params);
}

void MethodConfig::SetStageParam(const std::string& stage, const std::string& key, const std::string& value,
                                 const std::string& source) {
  for (StageConfig& sc : stages) {
    if (sc.name != stage) continue;
    auto it = sc.params.params.find(key);
    if (it == sc.params.params.end()) throw InputError(path, sc.params.line, "stage " + stage + " has no parameter " + key);
    it->second.value = value;
    it->second.list.clear();
    it->second.source = source;
    return;
  }
  throw InputError(path, "no stage " + stage + " in the config");
}

}  // namespace dynref
