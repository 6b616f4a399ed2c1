#include "verify/trace_model.h"

#include "verify/check.h"

#include <cstdlib>

#include "io/coco_classes.h"

namespace dynref::verify {
namespace {

bool AllDigits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// "true"/"false" as 1/0, else strtod over the whole text.
std::optional<double> Number(const std::string& text) {
  if (text == "true") return 1.0;
  if (text == "false") return 0.0;
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == nullptr || *end != '\0') return std::nullopt;
  return v;
}

std::string ParamText(const nlohmann::json& p) {
  const nlohmann::json& v = p.contains("value") ? p.at("value") : p;
  return v.is_string() ? v.get<std::string>() : v.dump();
}

}  // namespace

TraceModel::TraceModel(trace::TraceReader& reader) : path_(reader.path()), schema_version_(reader.schema_version()) {
  header_ = reader.header();
  for (size_t g = 0; g < reader.groups().size(); ++g) {
    FrameRecords fr;
    fr.frame = reader.groups()[g].frame;
    fr.records = reader.ReadGroup(g);
    frame_pos_[fr.frame] = frames_.size();
    std::map<int64_t, size_t> obs;
    for (size_t i = 0; i < fr.records.size(); ++i) {
      const trace::Record& r = fr.records[i];
      if (r.type == trace::RecordType::kObservation) obs[r.feature_index] = i;
      if (!r.entity.empty()) entity_[r.entity].push_back({frames_.size(), i});
    }
    obs_.push_back(std::move(obs));
    frames_.push_back(std::move(fr));
  }
  const std::string cfg = HeaderValue("config_json");
  if (!cfg.empty()) config_ = nlohmann::json::parse(cfg, nullptr, /*allow_exceptions=*/false);
  if (config_.is_discarded()) config_ = nlohmann::json();
  const std::string cam = HeaderValue("camera_json");
  if (!cam.empty()) {
    const nlohmann::json c = nlohmann::json::parse(cam, nullptr, false);
    if (c.is_object()) {
      camera_.present = true;
      camera_.fx = c.value("fx", 0.0), camera_.fy = c.value("fy", 0.0);
      camera_.cx = c.value("cx", 0.0), camera_.cy = c.value("cy", 0.0);
      camera_.bf = c.value("bf", 0.0), camera_.th_depth = c.value("th_depth", 0.0);
      camera_.width = c.value("width", 0), camera_.height = c.value("height", 0);
    }
  }
}

std::string TraceModel::HeaderValue(const std::string& key) const {
  for (const auto& [k, v] : header_)
    if (k == key) return v;
  return "";
}

bool TraceModel::HasStage(const std::string& stage) const {
  if (!config_.is_object() || !config_.contains("stages")) return false;
  for (const nlohmann::json& s : config_.at("stages"))
    if (s.value("name", "") == stage) return true;
  return false;
}

bool TraceModel::StageParam(const std::string& stage, const std::string& key, std::string* value) const {
  if (!config_.is_object() || !config_.contains("stages")) return false;
  for (const nlohmann::json& s : config_.at("stages")) {
    if (s.value("name", "") != stage || !s.contains("params")) continue;
    const nlohmann::json& p = s.at("params");
    if (!p.contains(key)) return false;
    *value = ParamText(p.at(key));
    return true;
  }
  return false;
}

std::set<int> TraceModel::StageClassIds(const std::string& stage, const std::string& key) const {
  std::set<int> ids;
  if (!config_.is_object() || !config_.contains("stages")) return ids;
  for (const nlohmann::json& s : config_.at("stages")) {
    if (s.value("name", "") != stage || !s.contains("params") || !s.at("params").contains(key)) continue;
    const nlohmann::json& p = s.at("params").at(key);
    const nlohmann::json& v = p.is_object() && p.contains("value") ? p.at("value") : p;
    for (const nlohmann::json& e : v) {
      if (e.is_number_integer()) ids.insert(e.get<int>());
      else if (e.is_string()) ids.insert(CocoClassId(e.get<std::string>()));
    }
  }
  return ids;
}

std::optional<double> TraceModel::StageNumber(const std::string& stage, const std::string& key) const {
  std::string text;
  if (!StageParam(stage, key, &text)) return std::nullopt;
  return Number(text);
}

std::optional<double> TraceModel::BackboneNumber(const std::string& key) const {
  if (!config_.is_object() || !config_.contains("backbone") || !config_.at("backbone").contains(key))
    return std::nullopt;
  return Number(ParamText(config_.at("backbone").at(key)));
}

std::optional<size_t> TraceModel::FramePos(int64_t frame) const {
  auto it = frame_pos_.find(frame);
  if (it == frame_pos_.end()) return std::nullopt;
  return it->second;
}

const trace::Record* TraceModel::Obs(size_t frame_pos, int64_t index) const {
  if (frame_pos >= obs_.size()) return nullptr;
  auto it = obs_[frame_pos].find(index);
  return it == obs_[frame_pos].end() ? nullptr : &frames_[frame_pos].records[it->second];
}

const std::vector<RecordRef>& TraceModel::EntityRecords(const std::string& id) const {
  static const std::vector<RecordRef> kNone;
  auto it = entity_.find(id);
  return it == entity_.end() ? kNone : it->second;
}

std::optional<double> Input(const trace::Record& r, const std::string& name) {
  for (const trace::NamedValue& v : r.inputs)
    if (v.name == name) return v.value;
  return std::nullopt;
}

bool ParseDottedId(const std::string& id, const std::string& prefix, int64_t* a, int64_t* b) {
  if (id.compare(0, prefix.size(), prefix) != 0) return false;
  const std::string rest = id.substr(prefix.size());
  const size_t dot = rest.find('.');
  if (dot == std::string::npos || !AllDigits(rest.substr(0, dot)) || !AllDigits(rest.substr(dot + 1))) return false;
  *a = std::stoll(rest.substr(0, dot));
  *b = std::stoll(rest.substr(dot + 1));
  return true;
}

bool ParseNumberId(const std::string& id, const std::string& prefix, int64_t* n) {
  if (id.compare(0, prefix.size(), prefix) != 0 || !AllDigits(id.substr(prefix.size()))) return false;
  *n = std::stoll(id.substr(prefix.size()));
  return true;
}

double AppliedMinConfidence(const TraceModel& t, const trace::Record& r, const std::string& stage, Check& c) {
  const double paper = c.Need(t.StageNumber(stage, "min_confidence"), "config " + stage + ".min_confidence");
  const std::optional<double> applied = Input(r, "applied_min_confidence");
  if (!applied) return paper;
  std::string scale;
  t.StageParam(stage, "threshold_scale", &scale);
  c.Same("config " + stage + ".threshold_scale (a mapped threshold)", std::string("detector"), scale);
  if (!(*applied >= 0 && *applied <= 1)) c.Near("applied_min_confidence in [0, 1]", paper, *applied, 0);
  return *applied;
}

}  // namespace dynref::verify
