// Re-emits decoded records through a TraceWriter (`trace bench --replay`, tests that plant a
// wrong record into a copy of a trace): one place that knows every record's writer call.
#pragma once
#include "trace/trace_reader.h"
#include "trace/trace_writer.h"

namespace dynref::trace {

// Writes `r` as it was read (a kFrame record begins its frame group).
void WriteRecord(TraceWriter& w, const Record& r);
// The RunHeader of a trace as read back (fixed keys, input hashes, extra keys in file order).
RunHeader HeaderOf(const TraceReader& reader);

}  // namespace dynref::trace
