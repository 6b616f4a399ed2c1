#include "trace/trace_dump.h"

#include <cstdio>

#include "core/format.h"

namespace dynref::trace {

void DumpOptions::Check() const {
  if (format != "csv" && format != "jsonl")
    throw InputError("--format", "unknown dump format '" + format + "' (expected csv|jsonl)");
}

bool EntityMatches(const std::string& entity, const std::string& wanted) {
  if (entity == wanted) return true;
  return entity.size() > wanted.size() && entity.compare(0, wanted.size(), wanted) == 0 &&
         entity[wanted.size()] == '@';
}

std::string FieldText(const FlatField& f) { return f.exact ? f.text : FormatDouble17(f.number); }

std::string CsvEscape(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string JsonEscape(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"') out += "\\\"";
    else if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
    } else out += static_cast<char>(c);
  }
  return out + "\"";
}

namespace {
// JSON numbers for finite floats, strings "nan"/"inf"/"-inf" otherwise.
std::string JsonNumber(double v) {
  const std::string t = FormatDouble17(v);
  if (t == "nan" || t == "inf" || t == "-inf") return "\"" + t + "\"";
  return t;
}

void WriteHeader(TraceReader& reader, const DumpOptions& options, std::ostream& out) {
  std::vector<std::pair<std::string, std::string>> kv = {
      {"schema_version", std::to_string(reader.schema_version())},
      {"level", LevelName(reader.level())},
      {"end_state", reader.end_state()},
      {"record_count", std::to_string(reader.record_count())},
      {"frame_groups", std::to_string(reader.groups().size())}};
  for (const auto& p : reader.header()) kv.push_back(p);
  if (options.format == "csv") {
    out << "key,value\n";
    for (const auto& [k, v] : kv) out << CsvEscape(k) << "," << CsvEscape(v) << "\n";
  } else {
    out << "{";
    for (size_t i = 0; i < kv.size(); ++i)
      out << (i ? "," : "") << JsonEscape(kv[i].first) << ":" << JsonEscape(kv[i].second);
    out << "}\n";
  }
}
}  // namespace

uint64_t WriteDump(TraceReader& reader, const DumpOptions& options, std::ostream& out) {
  options.Check();
  if (options.header) {
    WriteHeader(reader, options, out);
    return 0;
  }
  const bool csv = options.format == "csv";
  if (csv) out << "frame,type,stage,kind,entity,occurrence,field,value\n";
  uint64_t written = 0;
  const auto& groups = reader.groups();
  for (size_t gi = 0; gi < groups.size(); ++gi) {
    if (options.frame && groups[gi].frame != *options.frame) continue;
    for (const FlatRecord& f : FlattenGroup(reader.ReadGroup(gi))) {
      if (!options.stage.empty() && f.stage != options.stage) continue;
      if (!options.entity.empty() && !EntityMatches(f.entity, options.entity)) continue;
      ++written;
      if (csv) {
        const std::string prefix = std::to_string(f.frame) + "," + f.type + "," +
                                   CsvEscape(f.stage) + "," + f.kind + "," + CsvEscape(f.entity) +
                                   "," + std::to_string(f.occurrence) + ",";
        for (const FlatField& x : f.fields)
          out << prefix << CsvEscape(x.name) << "," << CsvEscape(FieldText(x)) << "\n";
      } else {
        out << "{\"frame\":" << f.frame << ",\"type\":\"" << f.type
            << "\",\"stage\":" << JsonEscape(f.stage) << ",\"kind\":\"" << f.kind
            << "\",\"entity\":" << JsonEscape(f.entity) << ",\"occurrence\":" << f.occurrence
            << ",\"fields\":{";
        for (size_t i = 0; i < f.fields.size(); ++i) {
          const FlatField& x = f.fields[i];
          out << (i ? "," : "") << JsonEscape(x.name) << ":"
              << (x.exact ? JsonEscape(x.text) : JsonNumber(x.number));
        }
        out << "}}\n";
      }
    }
  }
  return written;
}

}  // namespace dynref::trace
