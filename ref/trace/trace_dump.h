// Canonical text dump of a trace (README "Text dump"): byte-identical for identical traces.
#pragma once
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "trace/trace_reader.h"

namespace dynref::trace {

struct DumpOptions {
  std::optional<int64_t> frame;  // only this frame (seeks through the frame index)
  std::string stage;             // only records whose stage / call id equals this
  std::string entity;            // only records whose entity equals this or starts with "<this>@"
  std::string format = "csv";    // "csv" | "jsonl"
  bool header = false;           // print the run header instead of the records
  void Check() const;            // InputError naming the bad field
};

bool EntityMatches(const std::string& entity, const std::string& wanted);
// Text of one field value: FormatDouble17 for floats, the text for exact fields.
std::string FieldText(const FlatField& f);
std::string CsvEscape(const std::string& s);
std::string JsonEscape(const std::string& s);

// Writes the dump; returns the number of records written.
uint64_t WriteDump(TraceReader& reader, const DumpOptions& options, std::ostream& out);

}  // namespace dynref::trace
