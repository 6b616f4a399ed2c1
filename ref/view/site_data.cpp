#include "view/site_data.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parallel.h"
#include "eval/trajectory_eval.h"
#include "io/trajectory.h"
#include "trace/trace_feature.h"
#include "view/packed.h"

namespace dynref::view {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A float for JSON: non-finite values as the strings the trace dump uses.
json Number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

// Record schemas: (type, stage, kind, field names, exact flags) -> id, in order of first use.
class SchemaTable {
 public:
  int Id(const trace::FlatRecord& r) {
    std::string key = r.type + "|" + r.stage + "|" + r.kind;
    for (const trace::FlatField& f : r.fields) key += "|" + f.name + (f.exact ? "!" : "");
    auto it = ids_.find(key);
    if (it != ids_.end()) return it->second;
    json fields = json::array(), exact = json::array();
    for (const trace::FlatField& f : r.fields) fields.push_back(f.name), exact.push_back(f.exact ? 1 : 0);
    const int id = static_cast<int>(list_.size());
    list_.push_back({r.type, r.stage, r.kind, fields, exact});
    ids_.emplace(key, id);
    return id;
  }
  const json& list() const { return list_; }

 private:
  std::map<std::string, int> ids_;
  json list_ = json::array();
};

// The frame of a per-frame entity id "f12.3" (also "i4.2", "l5.1", "pl2.0", "r3.1"), else -1.
int64_t EntityFrame(const std::string& base) {
  size_t k = 0;
  while (k < base.size() && base[k] >= 'a' && base[k] <= 'z') ++k;
  const size_t dot = base.find('.', k);
  if (k == 0 || dot == std::string::npos || dot == k) return -1;
  for (size_t i = k; i < dot; ++i)
    if (base[i] < '0' || base[i] > '9') return -1;
  return std::stoll(base.substr(k, dot - k));
}

// Entity ids a record links to a frame group (the page loads those frames for the entity's
// history): its own mp/kf/ml/mpl entity (also "mp3@kf2"), a per-frame entity recorded in another
// frame's group, and the map point an OBS names (associated, else final).
void LandmarkLinks(const trace::FlatRecord& r, int64_t frame, std::vector<std::string>* out) {
  const std::string base = r.entity.substr(0, r.entity.find('@'));
  const int64_t own = EntityFrame(base);
  if (own >= 0 && own != frame) out->push_back(base);
  for (const char* p : {"mpl", "mp", "kf", "ml"}) {
    const std::string prefix(p);
    if (base.size() > prefix.size() && base.compare(0, prefix.size(), prefix) == 0 &&
        base.find('.') == std::string::npos) {
      out->push_back(base);
      break;
    }
  }
  for (const trace::FlatField& f : r.fields) {
    if (r.type == "obs" && (f.name == "map_point_id" || f.name == "associated_map_point_id") && f.text != "-1")
      out->push_back("mp" + f.text);
    // Frame lines / planes of a map line / plane (backbone structure records, input map_line / map_plane).
    if (r.type == "prob" && (f.name == "in.map_line" || f.name == "in.map_plane") && f.number >= 0)
      out->push_back((f.name == "in.map_line" ? "ml" : "mpl") + std::to_string(static_cast<int64_t>(f.number)));
  }
}

// `call(a, b, ..., "packed");` with each argument as ASCII JSON and `packed` the LZMA stream of
// `json_text` as a one-character-per-byte literal (packed.h LzmaLatin1; the page loads these files
// as windows-1252 and decodes them with site/lzma.js): frame chunks, the summary, the links.
std::string LzmaScript(const std::string& call, const json& args, const std::string& json_text) {
  std::string text = call + "(";
  for (const json& a : args) text += a.dump(-1, ' ', true) + ",";
  return text + "\"" + LzmaLatin1(json_text) + "\");\n";
}

// K frame groups in one file OUT/data/r<k>/c<n>.js: `VIEW.chunkZ(k, n, [head...], packed)` with
// packed the LZMA stream of the JSON array of the frames' columns (LZMA's window spans the chunk,
// where zlib's 32 KB held less than one frame: README.md "Size"). LZMA (preset 9e) is most of
// `dynref view`'s time, so complete chunks wait in a batch that `threads` threads compress at once
// (core/parallel.h); each file's bytes are those of one thread.
class ChunkWriter {
 public:
  ChunkWriter(std::string dir, int k, int per_chunk, int threads)
      : dir_(std::move(dir)), k_(k), per_chunk_(per_chunk), threads_(std::max(1, threads)) {}
  uint64_t Add(const json& head, const json& columns) {
    heads_.push_back(head);
    text_ += text_.empty() ? "[" : ",";
    text_ += columns.dump();
    if (heads_.size() < static_cast<size_t>(per_chunk_)) return 0;
    Close();
    return pending_.size() >= static_cast<size_t>(2 * threads_) ? WritePending() : 0;
  }
  uint64_t Flush() {
    Close();
    return WritePending();
  }

 private:
  struct Pending {
    int chunk;
    json heads;
    std::string text;
  };
  void Close() {
    if (heads_.empty()) return;
    pending_.push_back({chunk_++, heads_, text_ + "]"});
    heads_ = json::array();
    text_.clear();
  }
  uint64_t WritePending() {
    std::vector<std::string> scripts(pending_.size());
    ParallelFor(static_cast<int>(pending_.size()), threads_, [&](int i) {
      const Pending& p = pending_[static_cast<size_t>(i)];
      scripts[static_cast<size_t>(i)] = LzmaScript("VIEW.chunkZ", json::array({k_, p.chunk, p.heads}), p.text);
    });
    uint64_t bytes = 0;
    for (size_t i = 0; i < pending_.size(); ++i) {
      AtomicWriteFile(dir_ + "/c" + std::to_string(pending_[i].chunk) + ".js", scripts[i]);
      bytes += scripts[i].size();
    }
    pending_.clear();
    return bytes;
  }

  std::string dir_;
  int k_, per_chunk_, threads_, chunk_ = 0;
  json heads_ = json::array();
  std::string text_;
  std::vector<Pending> pending_;
};

// Trajectory against ground truth (synthetic or TUM folder): aligned positions and ATE per pose.
json TrajectoryData(const std::string& run_dir, const json& run_json) {
  json t = json::object();
  const std::string est_path = run_dir + "/trajectory.txt";
  const std::string seq = run_json.value("sequence", "");
  const std::string gt_path = seq + "/groundtruth.txt";
  if (!fs::exists(est_path) || seq.empty() || !fs::exists(gt_path)) return t;
  try {
    const TumTrajectory gt = ReadTumTrajectory(gt_path), est = ReadTumTrajectory(est_path);
    const AteResult ate = ComputeAte(gt, est, AteOptions{});
    json g = json::array(), e = json::array(), err = json::array();
    for (size_t m = 0; m < ate.matches.size(); ++m) {
      const Eigen::Vector3d pg = gt.poses[ate.matches[m].first].T_wc.translation();
      const Eigen::Vector3d pe = ate.alignment.Apply(est.poses[ate.matches[m].second].T_wc.translation());
      const double stamp = est.poses[ate.matches[m].second].stamp;
      g.push_back({pg.x(), pg.y(), pg.z()});
      e.push_back({pe.x(), pe.y(), pe.z()});
      err.push_back({stamp, ate.errors_m[m]});
    }
    t = {{"gt", g}, {"est", e}, {"ate", err}, {"rmse_m", ate.stats.rmse}};
  } catch (const std::exception& ex) {
    t = {{"error", ex.what()}};
  }
  return t;
}

// A frame's records as columns (packed.h): "order" = the schema id of each record in file
// order; "cols"[schema] = [entities, occurrences, one array per field], packed (PackColumns).
class FrameColumns {
 public:
  void Add(int schema, const trace::FlatRecord& r, int digits) {
    order_.push_back(schema);
    json& c = cols_[std::to_string(schema)];
    if (c.is_null()) {
      c = json::array({json::array(), json::array()});
      for (size_t i = 0; i < r.fields.size(); ++i) c.push_back(json::array());
    }
    c[0].push_back(r.entity);
    c[1].push_back(r.occurrence);
    for (size_t i = 0; i < r.fields.size(); ++i)
      c[2 + i].push_back(r.fields[i].exact ? json(r.fields[i].text) : RoundedNumber(r.fields[i].number, digits));
  }
  json Json() const { return {{"order", order_}, {"cols", PackColumns(cols_)}}; }

 private:
  json order_ = json::array();
  json cols_ = json::object();
};

// OUT/data/r<k>/links.js: the links `trace feature --follow` searches (trace_feature.h
// CollectFollowLinks), packed (LZMA): {"via": [names], "links": [a, b, via index, ...], "masks": [...]}.
uint64_t WriteFollowLinks(trace::TraceReader& reader, int k, const std::string& dir) {
  const trace::FollowLinks links = trace::CollectFollowLinks(reader);
  std::map<std::string, int> via_ids;
  json via = json::array(), flat = json::array();
  for (const trace::FollowLink& l : links.links) {
    auto it = via_ids.emplace(l.via, static_cast<int>(via_ids.size())).first;
    if (it->second == static_cast<int>(via.size())) via.push_back(l.via);
    flat.push_back(l.a), flat.push_back(l.b), flat.push_back(it->second);
  }
  const json data = {{"via", via}, {"links", flat}, {"masks", links.instance_masks}};
  const std::string text = LzmaScript("VIEW.linksZ", json::array({k}), data.dump());
  AtomicWriteFile(dir + "/links.js", text);
  return text.size();
}

}  // namespace

RunSite WriteRunData(const std::string& run_dir, int k, const std::string& out_dir, const DataOptions& options,
                     const std::map<int64_t, std::string>& image_for_frame, const std::string& divergence_json) {
  RunSite site;
  site.run_dir = run_dir;
  site.label = fs::path(run_dir).filename().string();
  if (site.label.empty()) site.label = fs::path(run_dir).parent_path().filename().string();
  trace::TraceReader reader(trace::ResolveTracePath(run_dir));
  json run_json = json::object();
  if (fs::exists(run_dir + "/run.json")) {
    std::ifstream in(run_dir + "/run.json");
    run_json = json::parse(in, nullptr, false);
    if (run_json.is_discarded()) throw InputError(run_dir + "/run.json", "not valid JSON");
  }
  const std::string dir = out_dir + "/data/r" + std::to_string(k);
  fs::create_directories(dir);
  SchemaTable schemas;
  std::map<std::string, std::vector<int64_t>> links;  // entity -> frames of other groups with its records
  std::map<std::string, json> counts;                 // "stage.name" -> [[frame, value]...]
  json frames = json::array(), stamps = json::array();
  ChunkWriter chunks(dir, k, options.chunk_frames, options.threads);
  for (size_t g = 0; g < reader.groups().size(); ++g) {
    const std::vector<trace::Record> raw = reader.ReadGroup(g);
    const std::vector<trace::FlatRecord> recs = trace::FlattenGroup(raw);
    const int64_t frame = reader.groups()[g].frame;
    double stamp = 0;
    FrameColumns columns;
    for (const trace::FlatRecord& r : recs) {
      if (r.type == "frame") stamp = r.fields.empty() ? 0 : r.fields[0].number;
      if (r.type == "count") counts[r.stage + "." + r.entity].push_back({frame, std::stoll(r.fields.at(0).text)});
      std::vector<std::string> lm;
      LandmarkLinks(r, frame, &lm);
      for (const std::string& id : lm) {
        std::vector<int64_t>& f = links[id];
        if (f.empty() || f.back() != frame) f.push_back(frame);
      }
      columns.Add(schemas.Id(r), r, options.digits);
    }
    auto img = image_for_frame.find(frame);
    const json head = {{"frame", frame}, {"stamp", Number(stamp)},
                       {"image", img == image_for_frame.end() ? "" : img->second}};
    site.data_bytes += chunks.Add(head, columns.Json());
    site.frames.push_back(frame);
    frames.push_back(frame);
    stamps.push_back(Number(stamp));
  }
  site.data_bytes += chunks.Flush();
  site.data_bytes += WriteFollowLinks(reader, k, dir);
  json header = json::object();
  for (const auto& [key, value] : reader.header())
    if (key != "config_json") header[key] = value;
  json link_json = json::object();
  for (const auto& [id, f] : links) link_json[id] = f;
  json count_json = json::object();
  for (auto& [name, series] : counts) count_json[name] = series;
  const json summary = {{"label", site.label},        {"run_dir", fs::absolute(run_dir).string()},
                        {"header", header},            {"end_state", reader.end_state()},
                        {"run", run_json},             {"schemas", schemas.list()},
                        {"frames", frames},            {"stamps", stamps},
                        {"links", link_json},          {"counts", count_json},
                        {"digits", options.digits},    {"image_scale", options.image_scale},
                        {"chunk_frames", options.chunk_frames},
                        {"trajectory", TrajectoryData(run_dir, run_json)},
                        {"divergence", divergence_json.empty() ? json() : json::parse(divergence_json)}};
  const std::string text = LzmaScript("VIEW.summaryZ", json::array({k}), summary.dump());
  AtomicWriteFile(dir + "/summary.js", text);
  site.data_bytes += text.size();
  return site;
}

}  // namespace dynref::view
