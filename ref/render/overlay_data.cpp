// What an overlay shows, gathered from the trace, run.json and the ground-truth folder.
#include <sys/stat.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "io/camera.h"
#include "render/overlay.h"

namespace dynref::render {

RunInfo ReadRunInfo(const std::string& run_or_trace) {
  RunInfo info;
  info.trace_path = trace::ResolveTracePath(run_or_trace);
  struct stat st {};
  const bool is_dir = ::stat(run_or_trace.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
  if (is_dir) {
    const std::string path = run_or_trace + "/run.json";
    std::ifstream f(path);
    if (f) {
      nlohmann::json j;
      try {
        f >> j;
      } catch (const nlohmann::json::exception& e) {
        throw InputError(path, std::string("not valid JSON: ") + e.what());
      }
      auto text = [&](const char* key) {
        return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
      };
      info.sequence = text("sequence");
      info.detections = text("detections");
      info.camera = text("camera");
      // The backbone writes the resolved camera as an object; its "name" is a preset or YAML path.
      if (j.contains("camera") && j["camera"].is_object() && j["camera"].contains("name") &&
          j["camera"]["name"].is_string()) {
        const std::string name = j["camera"]["name"].get<std::string>();
        struct stat cst {};
        if (IsCameraPresetName(name) || ::stat(name.c_str(), &cst) == 0) info.camera = name;
      }
    }
  }
  if (info.sequence.empty() || info.detections.empty()) {
    trace::TraceReader reader(info.trace_path);
    if (info.sequence.empty()) info.sequence = reader.HeaderValue("sequence_path");
    if (info.detections.empty()) info.detections = reader.HeaderValue("detections_dir");
  }
  if (info.sequence.empty())
    throw InputError(run_or_trace, "no sequence path in run.json or in the trace header");
  // Relative paths are relative to where `dynref run` was started; when they do not resolve
  // from here, try them relative to the run directory's parent.
  auto resolve = [&](std::string& path) {
    struct stat pst {};
    if (path.empty() || path[0] == '/' || ::stat(path.c_str(), &pst) == 0 || !is_dir) return;
    const std::string alt = run_or_trace + "/../" + path;
    if (::stat(alt.c_str(), &pst) == 0) path = alt;
  };
  resolve(info.sequence);
  resolve(info.detections);
  return info;
}

namespace {

// Parses "f<frame>.<index>" -> index for the given frame; -1 otherwise.
int64_t FeatureIndexOf(const std::string& entity, int64_t frame) {
  const std::string prefix = "f" + std::to_string(frame) + ".";
  if (entity.compare(0, prefix.size(), prefix) != 0) return -1;
  try {
    size_t used = 0;
    const long long v = std::stoll(entity.substr(prefix.size()), &used);
    return used == entity.size() - prefix.size() ? v : -1;
  } catch (const std::logic_error&) {
    return -1;
  }
}

double InputOr(const trace::Record& r, const char* name, double fallback, bool* found) {
  for (const trace::NamedValue& nv : r.inputs)
    if (nv.name == name) return nv.value;
  *found = false;
  return fallback;
}

// PROB loop.transform on kf<keyframe> with inputs loop_kf and moved_m (ref/loop/README.md).
OverlayLoop LoopOf(const trace::Record& r) {
  OverlayLoop l;
  if (r.entity.size() > 2 && r.entity.compare(0, 2, "kf") == 0) l.keyframe = std::atoll(r.entity.c_str() + 2);
  bool found = true;
  l.loop_keyframe = static_cast<int64_t>(InputOr(r, "loop_kf", -1, &found));
  l.moved_m = InputOr(r, "moved_m", 0, &found);
  return l;
}

// One frame being collected: its overlay and the per-entity values to resolve at the end.
struct OverlayDataFrameState {
  OverlayFrame of;
  std::map<int64_t, double> feature_prob;
  std::map<int64_t, int> feature_decision, map_point_decision;
  std::map<std::string, size_t> shape_of;
};

OverlayShape& OverlayDataShape(const trace::Record& r, OverlayDataFrameState* st) {
  auto it = st->shape_of.find(r.entity);
  if (it == st->shape_of.end()) {
    it = st->shape_of.emplace(r.entity, st->of.shapes.size()).first;
    OverlayShape s;
    s.kind = r.kind;
    s.entity = r.entity;
    st->of.shapes.push_back(s);
  }
  return st->of.shapes[it->second];
}

int OverlayDataInstanceId(const std::string& e, int64_t frame) {
  const std::string prefix = "i" + std::to_string(frame) + ".";
  if (e.compare(0, prefix.size(), prefix) != 0) return -1;
  return std::atoi(e.c_str() + prefix.size());
}

// A line sample / plane / pixel region record: decision, probability and geometry inputs.
void OverlayDataShapeRecord(const trace::Record& r, bool prob, OverlayShape& s) {
  using trace::EntityKind;
  if (!prob) {
    s.decision = r.kept ? 1 : 0;
    return;
  }
  // The backbone's geometry record (stage "structure", written after the final pose)
  // carries no probability: it must not overwrite a method's.
  if (r.stage != trace::kGeometryStage) s.has_prob = true, s.prob = r.after;
  bool found = true;
  const bool line = r.kind == EntityKind::kLineSample;
  const double x0 = InputOr(r, line ? "x0" : "x_min", s.x0, &found);
  const double y0 = InputOr(r, line ? "y0" : "y_min", s.y0, &found);
  const double x1 = InputOr(r, line ? "x1" : "x_max", s.x1, &found);
  const double y1 = InputOr(r, line ? "y1" : "y_max", s.y1, &found);
  if (found) s.x0 = x0, s.y0 = y0, s.x1 = x1, s.y1 = y1;
  bool has_id = true;
  const double id = InputOr(r, line ? "map_line" : "map_plane", -1, &has_id);
  if (has_id) s.landmark = static_cast<int64_t>(id);
}

// A PROB or DECISION record, by the kind of entity it is about.
void OverlayDataEntityRecord(const trace::Record& r, int64_t frame, OverlayDataFrameState* st,
                             std::map<int64_t, double>* map_point_prob) {
  using trace::EntityKind;
  const bool mp = r.entity.size() > 2 && r.entity.compare(0, 2, "mp") == 0;
  const bool prob = r.type == trace::RecordType::kProbability;
  if (r.kind == EntityKind::kKeyFrame) {
    if (prob && r.stage == "loop.transform") st->of.loops.push_back(LoopOf(r));
  } else if (r.kind == EntityKind::kMapPoint && mp) {
    const int64_t id = std::atoll(r.entity.c_str() + 2);
    if (prob) (*map_point_prob)[id] = r.after;
    else st->map_point_decision[id] = r.kept ? 1 : 0;
  } else if (r.kind == EntityKind::kFeature) {
    const int64_t idx = FeatureIndexOf(r.entity, frame);
    if (idx < 0) return;
    if (prob) st->feature_prob[idx] = r.after;
    else st->feature_decision[idx] = r.kept ? 1 : 0;
  } else if (r.kind == EntityKind::kInstanceMask) {
    const int id = OverlayDataInstanceId(r.entity, frame);
    if (id < 0) return;
    OverlayInstanceState& s = st->of.instances[id];
    if (prob) s.has_prob = true, s.prob = r.after;
    else s.decision = r.kept ? 1 : 0;
  } else if (r.kind == EntityKind::kLineSample || r.kind == EntityKind::kPlane ||
             r.kind == EntityKind::kPixelRegion) {
    OverlayDataShapeRecord(r, prob, OverlayDataShape(r, st));
  }
}

void OverlayDataRecord(const trace::Record& r, int64_t frame, OverlayDataFrameState* st,
                       std::map<int64_t, double>* map_point_prob) {
  using trace::RecordType;
  switch (r.type) {
    case RecordType::kFrame: st->of.timestamp = r.timestamp; break;
    case RecordType::kCount: st->of.counts.push_back({r.stage + "." + r.name, r.value}); break;
    case RecordType::kObservation: {
      OverlayFeature f;
      f.index = r.feature_index, f.map_point_id = r.map_point_id, f.u = r.u, f.v = r.v;
      st->of.features.push_back(f);
      break;
    }
    case RecordType::kProbability:
    case RecordType::kDecision:
      OverlayDataEntityRecord(r, frame, st, map_point_prob);
      break;
    default: break;
  }
}

// Features take their own P / decision, else their map point's; shapes without geometry inputs
// cannot be drawn.
void OverlayDataResolve(const std::map<int64_t, double>& map_point_prob, OverlayDataFrameState* st) {
  for (OverlayFeature& f : st->of.features) {
    auto fp = st->feature_prob.find(f.index);
    auto mpp = map_point_prob.find(f.map_point_id);
    if (fp != st->feature_prob.end()) f.has_prob = true, f.prob = fp->second;
    else if (f.map_point_id >= 0 && mpp != map_point_prob.end()) f.has_prob = true, f.prob = mpp->second;
    auto fd = st->feature_decision.find(f.index);
    auto md = st->map_point_decision.find(f.map_point_id);
    if (fd != st->feature_decision.end()) f.decision = fd->second;
    else if (f.map_point_id >= 0 && md != st->map_point_decision.end()) f.decision = md->second;
  }
  std::vector<OverlayShape> drawable;
  for (const OverlayShape& s : st->of.shapes)
    if (s.x0 != s.x1 || s.y0 != s.y1) drawable.push_back(s);
  st->of.shapes = std::move(drawable);
}
}  // namespace

std::vector<OverlayFrame> CollectOverlayFrames(trace::TraceReader& reader, int64_t first, int64_t last) {
  std::map<int64_t, double> map_point_prob;  // carried across frames
  std::vector<OverlayFrame> out;
  for (size_t gi = 0; gi < reader.groups().size(); ++gi) {
    const int64_t frame = reader.groups()[gi].frame;
    if (frame > last) break;
    const std::vector<trace::Record> recs = reader.ReadGroup(gi);
    const bool wanted = frame >= first;
    OverlayDataFrameState st;
    st.of.frame = frame;
    for (const trace::Record& r : recs) OverlayDataRecord(r, frame, &st, &map_point_prob);
    if (!wanted) continue;
    OverlayDataResolve(map_point_prob, &st);
    out.push_back(std::move(st.of));
  }
  return out;
}

GroundTruthLabels::GroundTruthLabels(const std::string& root) : reader_(root + "/gt") {
  const std::string path = root + "/gt/moving.txt";
  std::ifstream f(path);
  if (!f) throw InputError(path, "cannot open (needed for --gt)");
  std::string line;
  int n = 0;
  while (std::getline(f, line)) {
    ++n;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string stamp;
    s >> stamp;
    std::set<int>& ids = moving_[stamp];
    int id;
    while (s >> id) ids.insert(id);
    if (!s.eof()) throw InputError(path, n, "expected '<rgb stamp> <moving instance ids...>'");
  }
}

std::set<int> GroundTruthLabels::Moving(const std::string& stamp_text) const {
  auto it = moving_.find(stamp_text);
  return it == moving_.end() ? std::set<int>{} : it->second;
}

bool GtFrame::IsDynamic(double u, double v) const {
  if (instance_ids.empty()) return false;
  const int x = static_cast<int>(std::floor(u + 0.5)), y = static_cast<int>(std::floor(v + 0.5));
  if (x < 0 || y < 0 || x >= instance_ids.cols || y >= instance_ids.rows) return false;
  return moving.count(instance_ids.at<uint16_t>(y, x)) > 0;
}

}  // namespace dynref::render
