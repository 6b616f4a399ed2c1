// `dynref trace feature RUN ID`: every record in a trace that concerns one feature or map point.
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "trace/trace_reader.h"

namespace dynref::trace {

struct FeatureHistory {
  std::string id;
  std::vector<FlatRecord> rows;  // processing order (frames ascending, file order within)
};

// Matches: records whose entity is `id` or starts with "<id>@" (residual observation ids); for
// "mp<N>", observations matched to map point N and every record of those feature observations
// ("f<frame>.<index>") in the same frame; for a map line "ml<N>" / map plane "mpl<N>", every record
// of the frame lines "l<frame>.<i>" / planes "pl<frame>.<i>" whose structure record names it
// (input map_line / map_plane); for "f<frame>.<index>", the observation itself.
FeatureHistory CollectFeatureHistory(TraceReader& reader, const std::string& id);
// True for a canonical entity id (README "Canonical entity ids"): f|i|l|pl|r<frame>.<index>,
// mp|kf|ml|mpl<id>, optionally followed by a residual suffix "@f<frame>" or "@kf<id>".
bool IsCanonicalEntityId(const std::string& id);
// CSV table: frame,type,stage,kind,entity,occurrence,fields ("name=value" separated by spaces).
void WriteFeatureTable(const FeatureHistory& history, std::ostream& out);

}  // namespace dynref::trace
