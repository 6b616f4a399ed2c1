// `dynref trace feature RUN ID --follow`: the chain of entities that are the same physical
// feature (or line, or instance mask) across the run, and every record of them
// (ref/trace/README.md "Following a feature").
#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <ostream>
#include <set>
#include <tuple>

#include "trace/trace_dump.h"
#include "trace/trace_feature.h"

namespace dynref::trace {
namespace {

// "f20.2" -> prefix "f", frame 20, index 2; "mp34" -> prefix "mp", frame -1, index 34.
struct ParsedId {
  std::string prefix;
  int64_t frame = -1, index = -1;
  bool per_frame = false;
};
ParsedId ParseId(const std::string& id) {
  ParsedId p;
  size_t k = 0;
  while (k < id.size() && id[k] >= 'a' && id[k] <= 'z') ++k;
  p.prefix = id.substr(0, k);
  const size_t dot = id.find('.', k);
  try {
    if (dot == std::string::npos) {
      p.index = std::stoll(id.substr(k));
    } else {
      p.per_frame = true;
      p.frame = std::stoll(id.substr(k, dot - k));
      p.index = std::stoll(id.substr(dot + 1));
    }
  } catch (const std::exception&) {  // not canonical: kept as text only
  }
  return p;
}

std::string BaseId(const std::string& entity) { return entity.substr(0, entity.find('@')); }

// A non-negative integer input value (ids, indices), else -1.
int64_t IdValue(double v) {
  if (!std::isfinite(v) || v < 0 || v != std::floor(v)) return -1;
  return static_cast<int64_t>(v);
}

// A residual link (the backbone's `*.obs` records, AddResidualLink): a reference the chain shows
// one hop from where it was reached, never followed further (README "Following a feature").
bool IsResidualLink(const std::string& via) { return via.compare(0, 10, "residual (") == 0; }

class LinkGraph {
 public:
  void Link(const std::string& a, const std::string& b, const std::string& via) {
    if (a == b) return;
    // The first link between two entities names it (both directions are new together), except
    // that an identity link replaces a residual one (listed again: site/view.js does the same).
    auto [it, fresh] = adjacency_[a].emplace(b, via);
    if (!fresh && !(IsResidualLink(it->second) && !IsResidualLink(via))) return;
    it->second = via;
    adjacency_[b][a] = via;
    links_.links.push_back({a, b, via});
  }
  void Instance(int64_t inst, const std::string& entity) {
    if (instances_[inst].insert(entity).second) links_.instance_masks.push_back(entity);
  }
  const FollowLinks& links() const { return links_; }

  // Breadth-first search from `start` (README "Following a feature"). Previous-frame links never
  // turn around in time: the start is followed both ways, an entity reached backwards (an
  // earlier frame) only further back, one reached forwards only further forward, so siblings
  // (two features naming the same previous feature) do not join through their common ancestor.
  // A landmark (mp / ml / mpl) brings in every entity linked to it in every frame, each followed
  // on in the direction of its frame from the entity the landmark was first reached from (both
  // ways when the landmark is the start) -- but only a landmark of the start's own track (entities
  // reached from the start through previous-frame links): the landmarks of entities a landmark
  // brought in join the chain without bringing in theirs, or the chain of a feature of a
  // long-lived map point closes over most of the run. Residual links are one-hop references: the entity at
  // their other end joins the chain but is not searched from (a landmark reached only through a
  // residual brings in nothing; an entity reached only through one is not followed on). Masks
  // join every mask with the same instance id.
  std::vector<ChainEntry> Closure(const std::string& start) const {
    enum : int { kBack = 1, kForward = 2, kBoth = 3 };
    std::map<std::string, ChainEntry> seen;
    std::map<std::string, int> expanded;  // directions already searched from an entity
    std::deque<std::tuple<std::string, int, bool>> queue;  // entity, directions, on the start's track
    std::set<std::string> landmarks_done;  // landmarks whose entities have joined
    // `core`: reached from the start through previous-frame links only (or an entity of the start
    // landmark); only such an entity's landmarks bring in their entities. A core search of a
    // direction also covers a non-core one: expanded holds dir | dir << 2 for core, dir otherwise.
    const auto visit = [&](const std::string& e, int dir, const std::string& via, const std::string& from, bool core) {
      if (!seen.count(e)) {
        ChainEntry c;
        c.entity = e;
        const ParsedId p = ParseId(e);
        c.frame = p.per_frame ? p.frame : -1;
        c.via = via;
        c.from = from;
        seen.emplace(e, std::move(c));
      }
      int& done = expanded[e];
      const int mask = core ? dir | dir << 2 : dir;
      if ((done | mask) == done) return;
      done |= mask;
      queue.emplace_back(e, dir, core);
    };
    // Direction of an entity in frame `to` reached from frame `from` (moving in `dir`).
    const auto towards = [](int64_t from, int64_t to, int dir) { return to < from ? kBack : to > from ? kForward : dir; };
    visit(start, kBoth, "start", "", true);
    while (!queue.empty()) {
      const auto [e, dir, core] = queue.front();
      queue.pop_front();
      const ParsedId p = ParseId(e);
      auto it = adjacency_.find(e);
      if (!p.per_frame) {  // a landmark as the start: all its entities, both ways
        landmarks_done.insert(e);
        if (it != adjacency_.end())
          for (const auto& [next, via] : it->second) visit(next, IsResidualLink(via) ? 0 : kBoth, via, e, true);
        continue;
      }
      if (it != adjacency_.end())
        for (const auto& [next, via] : it->second) {
          const ParsedId q = ParseId(next);
          if (q.per_frame) {  // a previous-frame link: only in this entity's direction
            const int d = towards(p.frame, q.frame, dir);
            if (d & dir) visit(next, d, via, e, core);
            continue;
          }
          visit(next, 0, via, e, false);  // the landmark joins the chain, expanded once: from here
          if (!core || IsResidualLink(via) || !landmarks_done.insert(next).second) continue;
          auto lm = adjacency_.find(next);
          if (lm != adjacency_.end())
            for (const auto& [other, via2] : lm->second) {
              const ParsedId r = ParseId(other);
              if (r.per_frame) visit(other, IsResidualLink(via2) ? 0 : towards(p.frame, r.frame, dir), via2, next, false);
            }
        }
      if (p.prefix == "i") {
        auto inst = instances_.find(p.index);
        if (inst != instances_.end())
          for (const std::string& next : inst->second) visit(next, kBoth, "instance id", e, core);
      }
    }
  std::vector<ChainEntry> out;
    for (auto& [id, c] : seen) out.push_back(std::move(c));
    // Per-frame entities by (frame, prefix, index), then landmarks by (prefix, index).
    const auto key = [](const ChainEntry& c) {
      const ParsedId p = ParseId(c.entity);
      return std::make_tuple(p.per_frame ? 0 : 1, p.frame, p.prefix, p.index, c.entity);
    };
    std::stable_sort(out.begin(), out.end(), [&](const ChainEntry& a, const ChainEntry& b) { return key(a) < key(b); });
    return out;
  }

 private:
  std::map<std::string, std::map<std::string, std::string>> adjacency_;
  std::map<int64_t, std::set<std::string>> instances_;  // inst -> i<F>.<inst> over all frames
  FollowLinks links_;  // the same links in order of first appearance (CollectFollowLinks)
};

// A residual link record (the backbone's `track.pose.obs` / `localba.obs`, README "Geometry
// inputs") on "<landmark>@f<F>" or "<landmark>@kf<K>" with input feature / line / plane: the
// per-frame entity observing the landmark.
void AddResidualLink(const Record& r, const std::map<int64_t, int64_t>& kf_frame, LinkGraph& g) {
  const size_t at = r.entity.find('@');
  const std::string base = r.entity.substr(0, at), where = r.entity.substr(at + 1);
  const ParsedId landmark = ParseId(base), place = ParseId(where);
  if (landmark.per_frame || landmark.index < 0 || place.per_frame || place.index < 0) return;
  int64_t frame = -1;
  if (place.prefix == "f") frame = place.index;
  if (place.prefix == "kf") {
    auto it = kf_frame.find(place.index);
    if (it != kf_frame.end()) frame = it->second;
  }
  if (frame < 0) return;
  const char* input = landmark.prefix == "mp" ? "feature" : landmark.prefix == "ml" ? "line"
                    : landmark.prefix == "mpl" ? "plane" : nullptr;
  const char* prefix = landmark.prefix == "mp" ? "f" : landmark.prefix == "ml" ? "l" : "pl";
  if (input == nullptr) return;
  for (const NamedValue& in : r.inputs)
    if (in.name == input && IdValue(in.value) >= 0)
      g.Link(prefix + std::to_string(frame) + "." + std::to_string(IdValue(in.value)), base,
             "residual (" + r.stage + ")");
}

// Links of one frame group's records (README "Following a feature"). kf_frame: keyframe id ->
// frame, from the PROB records on kf<K> with input `frame` (stage track.keyframe).
void AddLinks(const std::vector<Record>& records, int64_t prev_frame, std::map<int64_t, int64_t>& kf_frame,
              LinkGraph& g) {
  for (const Record& r : records) {
    if (r.type == RecordType::kProbability && r.entity.find('@') != std::string::npos) {
      AddResidualLink(r, kf_frame, g);
      continue;
    }
    if (r.type == RecordType::kProbability && r.entity.compare(0, 2, "kf") == 0) {
      const ParsedId k = ParseId(r.entity);
      for (const NamedValue& in : r.inputs)
        if (in.name == "frame" && !k.per_frame && k.index >= 0 && IdValue(in.value) >= 0)
          kf_frame[k.index] = IdValue(in.value);
      continue;
    }
    if (r.type == RecordType::kObservation) {
      if (r.associated_map_point_id >= 0)
        g.Link("f" + std::to_string(r.frame) + "." + std::to_string(r.feature_index),
               "mp" + std::to_string(r.associated_map_point_id), "map point (OBS)");
      continue;
    }
    if (r.type != RecordType::kProbability && r.type != RecordType::kDecision) continue;
    const ParsedId p = ParseId(r.entity);
    if (!p.per_frame) continue;
    if (p.prefix == "i") {
      g.Instance(p.index, r.entity);
      continue;
    }
    for (const NamedValue& in : r.inputs) {
      const int64_t v = IdValue(in.value);
      if (v < 0) continue;
      if (in.name == "prev_index" && prev_frame >= 0 && (p.prefix == "f" || p.prefix == "l"))
        g.Link(r.entity, p.prefix + std::to_string(prev_frame) + "." + std::to_string(v), "prev_index");
      else if (in.name == "map_point" && p.prefix == "f")
        g.Link(r.entity, "mp" + std::to_string(v), "map_point (" + r.stage + ")");
      else if (in.name == "map_line" && p.prefix == "l")
        g.Link(r.entity, "ml" + std::to_string(v), "map_line (" + r.stage + ")");
      else if (in.name == "map_plane" && p.prefix == "pl")
        g.Link(r.entity, "mpl" + std::to_string(v), "map_plane (" + r.stage + ")");
    }
  }
}

}  // namespace

bool IsCarrierStage(const std::string& stage) {
  // Geometry and link carriers with p = 0 (README "Geometry inputs"): structure, match.*, the
  // backbone's residual links (*.obs) and keyframe records (track.keyframe).
  const auto ends_with = [&](const char* s) {
    const std::string t(s);
    return stage.size() >= t.size() && stage.compare(stage.size() - t.size(), t.size(), t) == 0;
  };
  return stage == kGeometryStage || stage.compare(0, 6, "match.") == 0 || ends_with(".obs") ||
         stage == "track.keyframe";
}

// The first pass: the links of every frame group.
LinkGraph BuildLinkGraph(TraceReader& reader) {
  LinkGraph graph;
  std::map<int64_t, int64_t> kf_frame;
  int64_t prev_frame = -1, current = -1;
  for (size_t gi = 0; gi < reader.groups().size(); ++gi) {
    const int64_t frame = reader.groups()[gi].frame;
    if (frame != current) prev_frame = current, current = frame;  // a repeated group keeps its previous frame
    if (frame < 0) continue;
    AddLinks(reader.ReadGroup(gi), prev_frame, kf_frame, graph);
  }
  return graph;
}

FollowLinks CollectFollowLinks(TraceReader& reader) { return BuildLinkGraph(reader).links(); }

FeatureHistory CollectFollowHistory(TraceReader& reader, const std::string& id) {
  FeatureHistory h;
  h.id = id;
  h.follow = true;
  const LinkGraph graph = BuildLinkGraph(reader);
  h.chain = graph.Closure(BaseId(id));
  std::set<std::string> members;
  for (const ChainEntry& c : h.chain) members.insert(c.entity);
  // Records in frame order (groups are in processing order; sort by frame, keeping file order).
  std::map<int64_t, std::vector<size_t>> by_frame;
  for (size_t gi = 0; gi < reader.groups().size(); ++gi) by_frame[reader.groups()[gi].frame].push_back(gi);
  for (const auto& [frame, groups] : by_frame)
    for (size_t gi : groups)
      for (FlatRecord& f : FlattenGroup(reader.ReadGroup(gi)))
        if (f.type != "count" && members.count(BaseId(f.entity))) h.rows.push_back(std::move(f));
  return h;
}

void WriteChainSection(const FeatureHistory& h, std::ostream& out) {
  out << "# chain of " << h.id << ": " << h.chain.size() << " entities (frame -> entity, link)\n";
  for (const ChainEntry& c : h.chain)
    out << "# " << (c.frame >= 0 ? std::to_string(c.frame) : std::string("-")) << " -> " << c.entity << " ("
        << c.via << (c.from.empty() ? "" : ", from " + c.from) << ")\n";
}

}  // namespace dynref::trace
