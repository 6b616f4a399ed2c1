// `dynref trace feature RUN ID`: every record in a trace that concerns one feature or map point.
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "trace/trace_reader.h"

namespace dynref::trace {

// One entity of a followed chain (`trace feature --follow`).
struct ChainEntry {
  std::string entity;     // canonical id, e.g. "f19.3", "mp34", "l5.2", "ml3", "i4.2"
  int64_t frame = -1;     // the frame of a per-frame entity; -1 for a landmark (mp / ml / mpl)
  std::string via;        // the link that added it ("start", "prev_index", "map_point", ...)
  std::string from;       // the chain entity it was reached from ("" for the start)
};

struct FeatureHistory {
  std::string id;
  std::vector<FlatRecord> rows;  // processing order (frames ascending, file order within)
  bool follow = false;           // built by CollectFollowHistory
  std::vector<ChainEntry> chain; // follow: per-frame entities by (frame, id), then landmarks
};

// Matches: records whose entity is `id` or starts with "<id>@" (residual observation ids); for
// "mp<N>", observations matched to map point N and every record of those feature observations
// ("f<frame>.<index>") in the same frame; for a map line "ml<N>" / map plane "mpl<N>", every record
// of the frame lines "l<frame>.<i>" / planes "pl<frame>.<i>" whose structure record names it
// (input map_line / map_plane); for "f<frame>.<index>", the observation itself.
// The map point of a feature observation is OBS associated_map_point_id (schema 3: the point the
// stages saw, kept through exclusion and outlier flags).
FeatureHistory CollectFeatureHistory(TraceReader& reader, const std::string& id);
// `--follow` (README "Following a feature"): the chain of entities linked to `id` across the run,
// transitively, through (a) PROB inputs `prev_index` on f<F>.<i> / l<F>.<i> (index in the previous
// frame group), (b) PROB inputs `map_point` (f) / `map_line` (l) / `map_plane` (pl), (c) OBS
// associated_map_point_id (f <-> mp), (d) instance masks i<F>.<inst> with the same inst in any
// frame; rows = every record of every chain entity (and its residuals "<entity>@..."), frames
// ascending, file order within. Two passes over the trace (links, then records).
FeatureHistory CollectFollowHistory(TraceReader& reader, const std::string& id);
// The links `--follow` searches, for a client that follows chains itself (`dynref view`): one per
// pair of entities (named by its first link, e.g. "prev_index", "map point (OBS)"), in order of
// first appearance, and every instance mask entity i<F>.<inst> (joined by inst).
struct FollowLink {
  std::string a, b, via;
};
struct FollowLinks {
  std::vector<FollowLink> links;
  std::vector<std::string> instance_masks;
};
FollowLinks CollectFollowLinks(TraceReader& reader);
// "# chain of ID: N entities" then one "# <frame> -> <entity> (<via>, from <entity>)" line each.
void WriteChainSection(const FeatureHistory& history, std::ostream& out);
// PROB records that carry geometry or a match with p = 0 (stage "structure", stages "match.*"):
// not probabilities, so plots skip them.
bool IsCarrierStage(const std::string& stage);
// True for a canonical entity id (README "Canonical entity ids"): f|i|l|pl|r<frame>.<index>,
// mp|kf|ml|mpl<id>, optionally followed by a residual suffix "@f<frame>" or "@kf<id>".
bool IsCanonicalEntityId(const std::string& id);
// CSV table: frame,type,stage,kind,entity,occurrence,fields ("name=value" separated by spaces).
void WriteFeatureTable(const FeatureHistory& history, std::ostream& out);

}  // namespace dynref::trace
