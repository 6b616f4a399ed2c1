#include "trace/trace_source.h"

#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

namespace dynref::trace {
namespace {

bool IsExactField(const std::string& type, const std::string& name) {
  static const std::set<std::string> kExact = {"map_point_id", "associated_map_point_id", "octave", "descriptor_hash",
                                               "residual_kind", "inlier", "kept", "reason"};
  return kExact.count(name) > 0 || (type == "count" && name == "value");
}

[[noreturn]] void Bad(const std::string& file, int line, const std::string& what) {
  throw TraceError(file, TraceProblem::kCorrupt, "line " + std::to_string(line) + ": " + what);
}

}  // namespace

FlatRecord ParseJsonlRecord(const std::string& line, const std::string& file, int n) {
  nlohmann::ordered_json j;
  try {
    j = nlohmann::ordered_json::parse(line);
  } catch (const nlohmann::json::exception& e) {
    Bad(file, n, std::string("not JSON: ") + e.what());
  }
  auto text = [&](const char* key) -> std::string {
    if (!j.contains(key) || !j[key].is_string()) Bad(file, n, std::string("missing string \"") + key + "\"");
    return j[key].get<std::string>();
  };
  FlatRecord f;
  if (!j.contains("frame") || !j["frame"].is_number_integer()) Bad(file, n, "missing integer \"frame\"");
  f.frame = j["frame"].get<int64_t>();
  f.type = text("type");
  static const std::set<std::string> kTypes = {"frame", "pose", "count", "obs", "prob", "residual", "decision"};
  if (!kTypes.count(f.type)) Bad(file, n, "unknown record type '" + f.type + "'");
  f.stage = text("stage");
  f.kind = text("kind");
  f.entity = text("entity");
  if (!j.contains("fields") || !j["fields"].is_object()) Bad(file, n, "missing object \"fields\"");
  for (const auto& [name, v] : j["fields"].items()) {
    FlatField x;
    x.name = name;
    x.exact = IsExactField(f.type, name);
    if (x.exact) {
      if (v.is_string()) x.text = v.get<std::string>();
      else if (v.is_number_integer()) x.text = std::to_string(v.get<int64_t>());
      else Bad(file, n, "field " + name + " must be a string");
    } else if (v.is_number()) {
      x.number = v.get<double>();
    } else if (v.is_string() && (v == "nan" || v == "inf" || v == "-inf")) {
      const std::string s = v.get<std::string>();
      x.number = s == "nan" ? std::numeric_limits<double>::quiet_NaN()
                            : (s == "inf" ? 1 : -1) * std::numeric_limits<double>::infinity();
    } else {
      Bad(file, n, "field " + name + " must be a number (or \"nan\", \"inf\", \"-inf\")");
    }
    f.fields.push_back(std::move(x));
  }
  // A schema 1/2 dump has no associated_map_point_id: it equals map_point_id there (as the binary
  // reader fills it), placed right after it as Flatten does.
  if (f.type == "obs") {
    bool has_associated = false;
    size_t mp = f.fields.size();
    for (size_t i = 0; i < f.fields.size(); ++i) {
      if (f.fields[i].name == "associated_map_point_id") has_associated = true;
      if (f.fields[i].name == "map_point_id") mp = i;
    }
    if (!has_associated && mp < f.fields.size()) {
      FlatField a = f.fields[mp];
      a.name = "associated_map_point_id";
      f.fields.insert(f.fields.begin() + static_cast<long>(mp) + 1, std::move(a));
    }
  }
  return f;
}

TraceSource::TraceSource(const std::string& path) : path_(path) {
  const bool jsonl = path.size() > 6 && path.compare(path.size() - 6, 6, ".jsonl") == 0;
  if (!jsonl) {
    reader_ = std::make_unique<TraceReader>(path);
    for (size_t i = 0; i < reader_->groups().size(); ++i) groups_[reader_->groups()[i].frame].push_back(i);
    return;
  }
  std::ifstream in(path);
  if (!in) throw TraceError(path, TraceProblem::kUnreadable, "cannot open file");
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    FlatRecord f = ParseJsonlRecord(line, path, n);
    jsonl_[f.frame].push_back(std::move(f));
  }
  // Occurrences, as FlattenGroup assigns them.
  for (auto& [frame, recs] : jsonl_) {
    std::map<std::string, int> seen;
    for (FlatRecord& f : recs) f.occurrence = seen[f.type + "|" + f.stage + "|" + f.kind + "|" + f.entity]++;
  }
}

std::vector<int64_t> TraceSource::Frames() const {
  std::vector<int64_t> out;
  if (reader_)
    for (const auto& p : groups_) out.push_back(p.first);
  else
    for (const auto& p : jsonl_) out.push_back(p.first);
  return out;
}

std::vector<FlatRecord> TraceSource::Frame(int64_t frame) {
  if (!reader_) {
    auto it = jsonl_.find(frame);
    return it == jsonl_.end() ? std::vector<FlatRecord>{} : it->second;
  }
  auto it = groups_.find(frame);
  if (it == groups_.end()) return {};
  std::vector<Record> all;
  for (size_t g : it->second) {
    std::vector<Record> part = reader_->ReadGroup(g);
    all.insert(all.end(), std::make_move_iterator(part.begin()), std::make_move_iterator(part.end()));
  }
  return FlattenGroup(all);
}

}  // namespace dynref::trace
