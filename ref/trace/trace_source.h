// A trace as `dynref diff` sees it: frames of canonical flat records, from a binary trace.dtr
// (streamed one frame at a time) or from a canonical JSONL file (`*.jsonl`, the format of
// `dynref trace dump --format jsonl`, which another implementation may print instead of
// writing the binary format; README "Writing traces from another implementation").
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "trace/trace_reader.h"

namespace dynref::trace {

class TraceSource {
 public:
  // path ending in ".jsonl": JSONL (loaded whole); otherwise a binary trace. TraceError on a bad file.
  explicit TraceSource(const std::string& path);
  const std::string& path() const { return path_; }
  bool is_jsonl() const { return !reader_; }
  Level level() const { return reader_ ? reader_->level() : Level::kFull; }
  std::string HeaderValue(const std::string& key) const { return reader_ ? reader_->HeaderValue(key) : ""; }
  std::string end_state() const { return reader_ ? reader_->end_state() : ""; }
  std::vector<int64_t> Frames() const;              // ascending
  std::vector<FlatRecord> Frame(int64_t frame);      // file order, occurrences assigned

 private:
  std::string path_;
  std::unique_ptr<TraceReader> reader_;
  std::map<int64_t, std::vector<size_t>> groups_;    // binary: frame -> group indices
  std::map<int64_t, std::vector<FlatRecord>> jsonl_; // JSONL: frame -> records
};

// One canonical JSONL line -> flat record (occurrence 0). Fields named in README "Canonical
// view" as exact are text; every other field is a number or "nan"/"inf"/"-inf".
FlatRecord ParseJsonlRecord(const std::string& line, const std::string& file, int line_number);

}  // namespace dynref::trace
